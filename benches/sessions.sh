#!/usr/bin/env bash
# Session files (#31 item 3): a .btlog of RECORDS transitions (the recorded
# kitting run repeated) imported as a Parquet session and as JSON lines;
# prints each file's size and, in one run, the time and peak memory of
# `btx log FILE --node '#2'` on each (medians of 3).
#
#   benches/sessions.sh [RECORDS]   (10^6 by default)
set -euo pipefail
records=${1:-1000000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$records" "$dir/run.btlog"
imp() { local s; s=$(date +%s.%N); "$btx" -q import "$dir/run.btlog" --out "$1" 2>/dev/null; python3 -c "print(f'{$(date +%s.%N) - $s:.2f}')"; }
echo "import: to Parquet $(imp "$dir/run.parquet") s, to JSON lines $(imp "$dir/run.jsonl") s"
for f in run.btlog run.parquet run.jsonl; do
  times=(); rss=0
  for _ in 1 2 3; do
    out=$( { /usr/bin/time -f '%e %M' "$btx" -q log "$dir/$f" --node '#2' > /dev/null; } 2>&1 | tail -1)
    times+=("${out% *}"); rss=${out#* }
  done
  median=$(printf '%s\n' "${times[@]}" | sort -n | sed -n 2p)
  echo "$f: $(stat -c %s "$dir/$f") bytes, btx log ${median} s, peak $((rss / 1024)) MB"
done
