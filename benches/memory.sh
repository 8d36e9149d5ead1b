#!/usr/bin/env bash
# Memory per transition (#31 item 1): peak RSS of `btx log`, `btx why` at
# the last moment and `btx diff` on runs of RECORDS transitions (the
# recorded kitting run repeated, and "look at chuck fails once" repeated
# for the other side of the diff), as a .btlog and as the sessions
# imported from it (JSON lines and Parquet); prints bytes a transition
# beyond the peak of the same command on the one-run fixture.
#
#   benches/memory.sh [RECORDS]   (5·10^6 by default)
set -euo pipefail
records=${1:-5000000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$records" "$dir/a.btlog"
BTLOG=tests/fixtures/logs/kitting_lookat_fails_once.btlog python3 benches/repeat_btlog.py "$records" "$dir/b.btlog"
for side in a b; do
  "$btx" -q import "$dir/$side.btlog" --out "$dir/$side.parquet" 2>/dev/null
  "$btx" -q import "$dir/$side.btlog" --out "$dir/$side.jsonl" 2>/dev/null
done
peak() { { /usr/bin/time -f '%e %M' "$btx" -q "$@" > /dev/null; } 2>&1 | tail -1; }
base=$(peak log tests/fixtures/logs/kitting_nominal.btlog --node '#2' | cut -d' ' -f2)
for ext in btlog jsonl parquet; do
  for cmd in "log $dir/a.$ext --node #2" "why $dir/a.$ext status(#1)" "diff $dir/a.$ext $dir/b.$ext"; do
    read -r secs kib <<< "$(peak $cmd)"
    n=$records; [[ $cmd == diff* ]] && n=$((2 * records))
    echo "${cmd%% *} .$ext: ${secs} s, peak $((kib / 1024)) MB, $(( (kib - base) * 1024 / n )) bytes a transition"
  done
done
