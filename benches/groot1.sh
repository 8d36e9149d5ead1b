#!/usr/bin/env bash
# BehaviorTree.CPP 3 live (#30): btview's v3 mock (PyPI btview, a
# PublisherZMQ look-alike) ticking at HZ for TICKS ticks, watched by
# `btx watch`; prints the transitions the publisher counted as sent, those
# btx kept, whether they are the same in order, and watch's CPU time.
#
#   benches/groot1.sh [HZ] [TICKS]   (200, 4000: 20 s)
set -euo pipefail
hz=${1:-200}; ticks=${2:-4000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
py=target/oracle-venv/bin/python
[ -x "$py" ] || { echo "run cargo test --test groot1 once first (it makes $py)"; exit 1; }
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT
port=$(python3 -c "import socket; s=socket.socket(); s.bind(('127.0.0.1',0)); print(s.getsockname()[1])")
mkfifo "$dir/say"
"$py" tests/live/btview_v3.py "$port" $((port - 1)) "$hz" "$ticks" "$dir/sent.json" < "$dir/say" > "$dir/mock.out" &
exec 3> "$dir/say"
for _ in $(seq 100); do grep -q READY "$dir/mock.out" && break; sleep 0.1; done
secs=$(python3 -c "print(int($ticks / $hz) + 5)")
"$btx" watch ":$port" --for "$secs" --out "$dir/watched.jsonl" > /dev/null 2> "$dir/watch.err" &
watch=$!
for _ in $(seq 100); do grep -q '^watching' "$dir/watch.err" && break; sleep 0.1; done
echo go >&3
sleep $((secs - 2))
echo "watch CPU after $((secs - 2)) s: $(ps -o times= -p "$watch") s"
wait "$watch"
echo stop >&3
for _ in $(seq 100); do grep -q DONE "$dir/mock.out" && break; sleep 0.1; done
python3 - "$dir/sent.json" "$dir/watched.jsonl" <<'PY'
import json, sys
sent = [tuple(t) for t in json.load(open(sys.argv[1]))]
codes = {"IDLE": 0, "RUNNING": 1, "SUCCESS": 2, "FAILURE": 3}
kept, gaps = [], 0
with open(sys.argv[2]) as f:
    next(f)
    for line in f:
        r = json.loads(line)
        if r["k"] == "t":
            kept.append((r["uid"], codes[r["from"]], codes[r["to"]]))
        elif r["k"] == "g":
            gaps += 1
print(f"the publisher sent {len(sent)} transitions; btx kept {len(kept)}, {gaps} gaps; "
      f"{'the same, in order' if kept == sent else 'NOT the same'}")
PY
grep -v '^watching\|warning' "$dir/watch.err" || true
