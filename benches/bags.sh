#!/usr/bin/env bash
# Rosbags as light as logs (#42 item 5): one recorded run repeated to N
# transitions (benches/repeat_btlog.py) as a .btlog, and the same run as
# Nav2 would record it in a rosbag2 bag, MCAP and SQLite (tests/rosbag/
# write_bag.py, by the PyPI package `rosbags`: a message every 40 changes,
# Jazzy's definition); `btx log FILE --node '#2'` reads each whole (a bag
# needs --tree), and prints each one's time and peak memory, medians of 3,
# with the bytes a transition over btx's memory at rest (`btx --version`).
#
#   benches/bags.sh [N]   (1000000; needs target/oracle-venv, made by the
#                          tests: cargo test --release --test rosbag)
set -euo pipefail
n=${1:-1000000}
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx
btx=$PWD/target/release/btx
py=$PWD/target/oracle-venv/bin/python
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$n" "$dir/run.btlog"
"$py" tests/rosbag/write_bag.py "$dir/mcap" mcap jazzy "$dir/run.btlog" > /dev/null
"$py" tests/rosbag/write_bag.py "$dir/db3" sqlite3 jazzy "$dir/run.btlog" > /dev/null
# The tree the robot ran: the log's own, its SubTrees named as the bag
# names them (by ID: write_bag.py writes a node's name, else its ID).
python3 - "$dir/run.btlog" > "$dir/tree.xml" <<'PY'
import re, struct, sys
b = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<i", b, 19)[0]
xml = re.sub(r' _fullpath="[^"]*"', "", b[23:23 + n].decode())
print(xml.replace('<root BTCPP_format="4">', '<root BTCPP_format="4" main_tree_to_execute="MainTree">', 1))
PY
echo "machine load: $(cut -d' ' -f1-3 /proc/loadavg); $n transitions"
/usr/bin/time -f '%M' -o "$dir/rest" "$btx" --version > /dev/null
rest=$(cat "$dir/rest")
median() { sort -n | sed -n 2p; }
for f in run.btlog mcap db3; do
  extra=(); [ "$f" = run.btlog ] || extra=(--tree "$dir/tree.xml")
  for i in 1 2 3; do
    /usr/bin/time -f '%e %M' -o "$dir/t$i" "$btx" log "$dir/$f" "${extra[@]}" --node '#2' > /dev/null 2>&1
  done
  s=$(cat "$dir"/t[123] | cut -d' ' -f1 | median)
  kb=$(cat "$dir"/t[123] | cut -d' ' -f2 | median)
  echo "$f: $(du -sm "$dir/$f" | cut -f1) MB on disk; btx log --node '#2' $s s, $((kb / 1024)) MB peak, $(( (kb - rest) * 1024 / n )) B a transition"
done
