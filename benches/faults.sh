#!/usr/bin/env bash
# Faults told as they happen (#40 item 6): a robot (`btx serve`) whose
# tree, 100 leaves and a Fallback in a Repeat (208 transitions a tick), has
# its Flaky action fail every 50 ticks, served at RATE transitions a second
# and watched by `btx watch --format json` for SECONDS; prints, for each
# rate, the fault and recovery lines said, their latency (the robot's
# timestamp of the transition to the moment btx said the line: median and
# 99th percentile), the transitions kept, and watch's CPU time.
#
#   benches/faults.sh [SECONDS] [RATE ...]   (20, 10000 100000)
set -euo pipefail
secs=${1:-20}; shift || true
rates=("$@"); [ $# -gt 0 ] || rates=(10000 100000)
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT
leaves=$(printf '<AlwaysSuccess/>%.0s' $(seq 100))
printf '<root BTCPP_format="4"><BehaviorTree ID="Faults"><Repeat num_cycles="-1"><Sequence>%s<Fallback><Action ID="Flaky"/><AlwaysSuccess/></Fallback></Sequence></Repeat></BehaviorTree></root>\n' "$leaves" > "$dir/t.xml"
max=${rates[0]}; for r in "${rates[@]}"; do [ "$r" -gt "$max" ] && max=$r; done
ticks=$(( (secs + 10) * max / 200 ))
python3 -c "import sys; n=int(sys.argv[1]); print('Flaky = ' + ', '.join((['F'] + ['S'] * 49) * (n // 50 + 1)))" "$ticks" > "$dir/p.plan"
"$btx" -q run "$dir/t.xml" --plan "$dir/p.plan" --max-ticks "$ticks" --tick-ms 10 --out "$dir/served.jsonl" 2> /dev/null
per_tick=$(python3 -c "import json,sys; l=open(sys.argv[1]).readlines(); e=json.loads(l[-1]); print(e['transitions'] / e['ticks'])" "$dir/served.jsonl")
echo "served: $ticks ticks, $per_tick transitions a tick; machine load: $(cut -d' ' -f1-3 /proc/loadavg)"
for rate in "${rates[@]}"; do
  speed=$(python3 -c "print($rate / ($per_tick * 100))")
  "$btx" serve "$dir/served.jsonl" --port 0 --speed "$speed" --for $((secs + 30)) --buffer 100000 2> "$dir/serve.err" &
  serve=$!
  for _ in $(seq 50); do grep -q 'on 127.0.0.1:' "$dir/serve.err" 2>/dev/null && break; sleep 0.1; done
  port=$(sed -n 's/.* on 127\.0\.0\.1:\([0-9]*\) .*/\1/p' "$dir/serve.err" | head -1)
  /usr/bin/time -f '%U %S' -o "$dir/cpu" "$btx" watch ":$port" --for "$secs" --format json > "$dir/events.jsonl" 2> "$dir/watch.err"
  kill "$serve" 2>/dev/null || true; wait "$serve" 2>/dev/null || true
  python3 - "$rate" "$secs" "$dir/events.jsonl" "$dir/cpu" <<'PY'
import json, sys
rate, secs, events, cpu = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3], sys.argv[4]
lat, kept, said, first = [], 0, {}, None
for line in open(events):
    e = json.loads(line)
    if first is None and e.get("time_us"):
        first = e["time_us"]
    if "event" in e:
        said[e["event"]] = said.get(e["event"], 0) + 1
        if e["event"] in ("fault", "recovered") and e.get("time_us"):
            lat.append((e["time_us"] - first, (e["said_us"] - e["time_us"]) / 1000))
    else:
        kept += 1
def q(xs, p):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, round((len(xs) - 1) * p))] if xs else float("nan")
every = [l for _, l in lat]
# The first second holds btx's start: reading the tree, the first records.
steady = [l for t, l in lat if t > 1_000_000]
user, sys_ = map(float, open(cpu).read().split()[-2:])
print(f"{rate} a second: {kept} transitions kept ({kept / secs:.0f} a second); "
      f"{said.get('fault', 0)} faults, {said.get('recovered', 0)} recovered said; "
      f"latency median {q(every, 0.5):.1f} ms, 99th percentile {q(every, 0.99):.1f} ms "
      f"(after the first second: {q(steady, 0.5):.1f} ms, {q(steady, 0.99):.1f} ms, max {max(steady, default=float('nan')):.1f} ms); "
      f"watch CPU {user + sys_:.2f} s in {secs:.0f} s ({100 * (user + sys_) / secs:.1f} % of a core)")
PY
  grep -i 'gap\|error' "$dir/watch.err" | head -3 || true
done
