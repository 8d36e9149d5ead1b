#!/usr/bin/env bash
# A fleet's runs (#31 item 6): RUNS .btlog files of RECORDS transitions
# each (the recorded kitting run repeated, as benches/logs.rs makes its
# big log), ten robots' directories; times `cat` of every file, `btx fleet`
# over them (text, and with --export), and one `btx log FILE --node '#2'`
# a file, in one run, and prints btx fleet's peak memory.
#
#   benches/fleet.sh [RUNS] [RECORDS]   (1000, 10000: 10^7 transitions)
set -euo pipefail
runs=${1:-1000}; records=${2:-10000}
cd "$(dirname "$0")/.."
cargo build --release --quiet
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$records" "$dir/fleet" "$runs"
echo "$runs files of $records transitions: $(du -sh "$dir/fleet" | cut -f1)"
t() { local s; s=$(date +%s.%N); "$@" > /dev/null; python3 -c "print(f'{$(date +%s.%N) - $s:.2f}')"; }
cat_s=$(t sh -c "cat $dir/fleet/*/*.btlog")
fleet_s=$(t "$btx" -q fleet "$dir/fleet")
export_s=$(t "$btx" -q fleet "$dir/fleet" --export "$dir/export")
log_s=$(t sh -c "for f in $dir/fleet/*/*.btlog; do $btx log \$f --node '#2' > /dev/null; done")
rss=$( { /usr/bin/time -v "$btx" -q fleet "$dir/fleet" > /dev/null; } 2>&1 | awk '/Maximum resident/ {print $6}')
echo "cat: ${cat_s} s; btx fleet: ${fleet_s} s; with --export: ${export_s} s ($(du -sh "$dir/export" | cut -f1)); one btx log a file: ${log_s} s"
python3 -c "print(f'btx fleet / cat: {$fleet_s / max($cat_s, 0.01):.1f}x; btx fleet / one btx log a file: {$fleet_s / $log_s:.2f}x; peak memory {$rss / 1024:.0f} MB')"
