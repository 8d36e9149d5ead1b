#!/usr/bin/env bash
# The explorer at the end of a long log, in a real terminal (#42 item 3):
# a .btlog of RECORDS transitions (the recorded kitting run repeated,
# benches/repeat_btlog.py) opened by `btx open` in tmux (160×45, the
# screen polled every 5 ms); times the first frame (the log's first part,
# shown while the rest is read), the frame that shows it read whole
# ("of RECORDS" transitions), then `G` and, DELAY
# seconds later, `w` (the why-questions) and Enter (the first one's
# answer), RUNS times; and `btx log LOG --node '#2'` for the first frame's
# ratio, measured in the same run.
#
#   benches/explorer.sh [RECORDS] [DELAY] [RUNS]   (5000000 0.1 3)
set -euo pipefail
records=${1:-5000000}; delay=${2:-0.1}; runs=${3:-3}
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx
btx=$PWD/target/release/btx
dir=$(mktemp -d)
sock="btx-bench-$$"
trap 'tmux -L "$sock" kill-server 2>/dev/null || true; rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$records" "$dir/L.btlog"
echo "machine load: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; $records records"
now() { date +%s.%N; }
since() { python3 -c "print(f'{($(now) - $1) * 1000:.0f}')"; }
screen() { tmux -L "$sock" capture-pane -p -t b; }
# Waits (20 s at most) until the screen differs from file $1, or shows $1.
changed() { local n=0; while screen | cmp -s - "$1"; do sleep 0.005; n=$((n + 1)); [ $n -lt 4000 ] || { echo "the screen never changed" >&2; exit 1; }; done; }
shows() { local n=0; until screen | grep -q "$1"; do sleep 0.005; n=$((n + 1)); [ $n -lt 4000 ] || { echo "the screen never showed $1:" >&2; screen >&2; exit 1; }; done; }
for _ in $(seq "$runs"); do
  t=$(now)
  tmux -L "$sock" new-session -d -s b -x 160 -y 45 "$btx -q open $dir/L.btlog; sleep 30"
  shows "moment 1 "
  first=$(since "$t")
  shows "of $records"
  whole=$(since "$t")
  tmux -L "$sock" send-keys -t b G
  sleep "$delay"
  screen > "$dir/before"
  t=$(now); tmux -L "$sock" send-keys -t b w; changed "$dir/before"; w=$(since "$t")
  sleep 0.3; screen > "$dir/before"
  t=$(now); tmux -L "$sock" send-keys -t b Enter; changed "$dir/before"; enter=$(since "$t")
  tmux -L "$sock" send-keys -t b q
  tmux -L "$sock" kill-server
  t=$(now); "$btx" -q log "$dir/L.btlog" --node '#2' > /dev/null; node=$(since "$t")
  echo "first frame ${first} ms (btx log --node '#2' ${node} ms: $(python3 -c "print(f'{$first / $node:.2f}')")x), read whole ${whole} ms ($(python3 -c "print(f'{$whole / $node:.1f}')")x); w ${w} ms, Enter ${enter} ms, ${delay} s after G"
done
