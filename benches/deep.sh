#!/usr/bin/env bash
# Deep trees (#42 item 2): a chain of N SubTrees, each BehaviorTree a
# Sequence holding the next SubTree and an AlwaysSuccess (3 nodes and 2
# levels a link: N SubTrees make 3N nodes, 2N levels), loaded and printed
# by `btx tree` (text, then JSON), run for one tick by `btx run`, its causal
# graph printed by `btx graph` and its root's why asked by `btx why`; prints
# each one's time and peak memory, and the text's size, per N, so that how
# each grows with the depth reads off the rows.
#
#   benches/deep.sh [N ...]   (500 1000 2000 4000 8000 10000: 1,001 to
#                              20,001 levels)
set -euo pipefail
sizes=("$@"); [ $# -gt 0 ] || sizes=(500 1000 2000 4000 8000 10000)
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
: > "$dir/empty.plan"
echo "machine load: $(cut -d' ' -f1-3 /proc/loadavg)"
for n in "${sizes[@]}"; do
  python3 - "$n" > "$dir/chain.xml" <<'PY'
import sys
n = int(sys.argv[1])
print('<root BTCPP_format="4" main_tree_to_execute="T0">')
for i in range(n):
    print(f'<BehaviorTree ID="T{i}"><Sequence><SubTree ID="T{i + 1}"/><AlwaysSuccess/></Sequence></BehaviorTree>')
print(f'<BehaviorTree ID="T{n}"><AlwaysSuccess/></BehaviorTree>')
print('</root>')
PY
  measure() { /usr/bin/time -f '%e s, %M KB' -o "$dir/t" "$@" > "$dir/out" 2> /dev/null || echo "failed: $*" >&2; cat "$dir/t"; }
  text=$(measure "$btx" tree "$dir/chain.xml")
  size=$(du -m "$dir/out" | cut -f1)
  json=$(measure "$btx" tree "$dir/chain.xml" --format json)
  run=$(measure "$btx" run "$dir/chain.xml" --plan "$dir/empty.plan" --max-ticks 1 --out "$dir/s$n.jsonl")
  graph=$(measure "$btx" graph "$dir/s$n.jsonl")
  why=$(measure "$btx" why "$dir/s$n.jsonl" 'status(#1)' --at last)
  echo "$n SubTrees ($((3 * n + 1)) nodes, $((2 * n + 1)) levels): tree $text (${size} MB of text); tree --format json $json; run 1 tick $run; graph $graph; why $why"
done
