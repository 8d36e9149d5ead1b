#!/usr/bin/env bash
# Soak (#26): `btx watch --out` against `btx serve --buffer BUFFER` sending about 10^5
# transitions a second for SECONDS (default 60). Prints watch's resident
# memory each second (it must stay flat: the run streams to its file), then
# checks that every transition served was kept, in order, with no gap.
#
#   benches/soak.sh [SECONDS] [BUFFER]   (60 s; 10,000 kept between two reads; BehaviorTree.CPP keeps 1,000)
set -euo pipefail
secs=${1:-60}
buffer=${2:-10000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT

# 100 leaves in a Sequence: 203 transitions a tick. At 10 ms a tick and
# --speed 5, 500 ticks a second: about 101,500 transitions a second.
leaves=$(printf '<AlwaysSuccess/>%.0s' $(seq 100))
printf '<root BTCPP_format="4"><BehaviorTree ID="Soak"><Repeat num_cycles="-1"><Sequence>%s</Sequence></Repeat></BehaviorTree></root>\n' "$leaves" > "$dir/soak.xml"
: > "$dir/empty.plan"
ticks=$(( (secs + 5) * 500 ))
"$btx" -q run "$dir/soak.xml" --plan "$dir/empty.plan" --max-ticks "$ticks" --tick-ms 10 --out "$dir/served.jsonl"

"$btx" serve "$dir/served.jsonl" --port 0 --speed 5 --for $((secs + 30)) --buffer "$buffer" 2> "$dir/serve.err" &
for _ in $(seq 50); do grep -q 'on 127.0.0.1:' "$dir/serve.err" 2>/dev/null && break; sleep 0.1; done
port=$(sed -n 's/.* on 127\.0\.0\.1:\([0-9]*\) .*/\1/p' "$dir/serve.err" | head -1)

"$btx" watch ":$port" --for "$secs" --out "$dir/watched.jsonl" > /dev/null 2> "$dir/watch.err" &
watch=$!
echo "second  watch RSS (KiB)"
s=0
while kill -0 "$watch" 2>/dev/null; do
  rss=$(ps -o rss= -p "$watch" 2>/dev/null || true)
  [ -n "$rss" ] && printf '%6d  %s\n' "$s" "$rss" | tee -a "$dir/rss"
  sleep 1; s=$((s + 1))
done
wait "$watch"
cat "$dir/watch.err"

python3 - "$dir/served.jsonl" "$dir/watched.jsonl" "$dir/rss" <<'PY'
import json, sys
def transitions(path):
    with open(path) as f:
        next(f)
        for line in f:
            r = json.loads(line)
            if r["k"] == "t":
                yield (r["uid"], r["from"], r["to"])
            elif r["k"] == "g":
                yield ("gap",)
served, watched = transitions(sys.argv[1]), transitions(sys.argv[2])
n = 0
for w in watched:
    if w == ("gap",):
        sys.exit(f"FAIL: a gap after {n} transitions")
    s = next(served, None)
    if s != w:
        sys.exit(f"FAIL: transition {n + 1} differs: served {s}, watched {w}")
    n += 1
rss = [int(l.split()[1]) for l in open(sys.argv[3])]
half = len(rss) // 2
print(f"{n} transitions kept, in order, no gap")
print(f"watch RSS: {rss[1] if len(rss) > 1 else rss[0]} KiB after 1 s, "
      f"max {max(rss)} KiB, max of the second half {max(rss[half:])} KiB "
      f"vs first half {max(rss[:half] or rss)} KiB")
PY
