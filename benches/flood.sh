#!/usr/bin/env bash
# A Groot2 server flooding (#41 item 10): for each RECORDS, a server that
# answers every request for transitions with RECORDS of them (announcing a
# buffer of as many, so that btx takes every reply), watched by
# `btx watch --out` for SECONDS; prints watch's resident memory every 10 s
# (flat: each queue is bounded, and btx stops polling while it is full),
# its peak, and what the session kept. The session is written to a
# temporary folder and removed: at 10^5 a reply it grows about 150 MB a
# second, so have 10 GB free.
#
#   benches/flood.sh [SECONDS] [RECORDS ...]   (60, 10000 100000)
set -euo pipefail
secs=${1:-60}; shift || true
sizes=("${@:-10000}"); [ $# -gt 0 ] || sizes=(10000 100000)
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx --example flood_peer
btx=$PWD/target/release/btx
peer=$PWD/target/release/examples/flood_peer
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT
rss() { awk '/^VmRSS/ {print int($2 / 1024)}' "/proc/$1/status" 2>/dev/null || echo -; }
for n in "${sizes[@]}"; do
  coproc PEER { exec "$peer" sessions/kitting-nominal.jsonl "$n" "$n" $((secs + 30)); }
  read -r port <&"${PEER[0]}"
  /usr/bin/time -f '%M' -o "$dir/peak" "$btx" watch ":$port" --for "$secs" --out "$dir/w.jsonl" \
    > /dev/null 2> "$dir/watch.err" &
  timed=$!
  sleep 1
  watch=$(pgrep -P "$timed" -x btx || echo "$timed")
  line="$n a reply: RSS (MB)"
  sleep 4
  for t in $(seq 5 10 $((secs - 1))); do
    line="$line ${t}s: $(rss "$watch")"
    sleep 10
  done
  wait "$timed" || true
  kill "$PEER_PID" 2>/dev/null || true
  wait "$PEER_PID" 2>/dev/null || true
  kept=$(grep -c '"k":"t"' "$dir/w.jsonl" || true)
  gaps=$(grep -c '"k":"g"' "$dir/w.jsonl" || true)
  size=$(du -m "$dir/w.jsonl" | cut -f1)
  echo "$line; peak $(( $(cat "$dir/peak") / 1024 )) MB; kept $kept transitions ($((kept / secs)) a second, ${size} MB), $gaps gaps"
  grep -v '^watching' "$dir/watch.err" | grep -i 'left\|error\|gap' | head -3 || true
  rm -f "$dir/w.jsonl"
done
