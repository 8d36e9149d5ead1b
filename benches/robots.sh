#!/usr/bin/env bash
# Several robots (#30): ROBOTS `btx serve` instances, each sending RATE
# transitions a second (the soak's 100-leaf tree, 203 transitions a tick),
# watched by one `btx watch` for SECONDS into one session a robot; then
# every robot's session is checked against the run it served (in order,
# no gap), and watch's CPU time is printed.
#
#   benches/robots.sh [ROBOTS] [RATE] [SECONDS] [BUFFER]   (4, 25000, 30, 10000)
set -euo pipefail
robots=${1:-4}; rate=${2:-25000}; secs=${3:-30}; buffer=${4:-10000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT

leaves=$(printf '<AlwaysSuccess/>%.0s' $(seq 100))
printf '<root BTCPP_format="4"><BehaviorTree ID="Soak"><Repeat num_cycles="-1"><Sequence>%s</Sequence></Repeat></BehaviorTree></root>\n' "$leaves" > "$dir/soak.xml"
: > "$dir/empty.plan"
# 203 transitions a tick at 10 ms a tick: --speed gives RATE a second.
speed=$(python3 -c "print($rate / 20300)")
ticks=$(python3 -c "import math; print(math.ceil(($secs + 10) * $rate / 203))")
"$btx" -q run "$dir/soak.xml" --plan "$dir/empty.plan" --max-ticks "$ticks" --tick-ms 10 --out "$dir/served.jsonl"
eps=()
for i in $(seq "$robots"); do
  "$btx" serve "$dir/served.jsonl" --port 0 --speed "$speed" --for $((secs + 40)) --buffer "$buffer" 2> "$dir/serve$i.err" &
  for _ in $(seq 50); do grep -q 'on 127.0.0.1:' "$dir/serve$i.err" 2>/dev/null && break; sleep 0.1; done
  eps+=(":$(sed -n 's/.* on 127\.0\.0\.1:\([0-9]*\) .*/\1/p' "$dir/serve$i.err" | head -1)")
done
"$btx" watch "${eps[@]}" --for "$secs" --out "$dir/fleet" > /dev/null 2> "$dir/watch.err" &
watch=$!
sleep $((secs - 2))
echo "watch CPU (s) after $((secs - 2)) s: $(ps -o times= -p "$watch")"
wait "$watch"
grep -c "^\[.*gap after" "$dir/watch.err" | sed 's/^/gaps: /' || true
python3 - "$dir/served.jsonl" "$dir/fleet" <<'PY'
import json, os, sys
def transitions(path):
    with open(path) as f:
        next(f)
        for line in f:
            r = json.loads(line)
            if r["k"] == "t":
                yield (r["uid"], r["from"], r["to"])
            elif r["k"] == "g":
                yield ("gap",)
total = 0
for name in sorted(os.listdir(sys.argv[2])):
    if not name.endswith(".jsonl"):
        continue
    served = transitions(sys.argv[1])
    n = 0
    for w in transitions(os.path.join(sys.argv[2], name)):
        if w == ("gap",):
            sys.exit(f"FAIL: {name}: a gap after {n} transitions")
        if next(served, None) != w:
            sys.exit(f"FAIL: {name}: transition {n + 1} differs")
        n += 1
    print(f"{name}: {n} transitions kept, in order, no gap")
    total += n
print(f"{total} transitions in all")
PY
