#!/usr/bin/env bash
# Reading a log near the floor (#42 item 1): a .btlog of RECORDS
# transitions (the recorded kitting run repeated, benches/repeat_btlog.py)
# read by `cat`, by the 20-line Python reader (benches/read_btlog.py), and
# by `btx log`, one node's rows and every row; the median of RUNS runs of
# each, and each as a ratio to the Python reader measured in the same run.
#
#   benches/reading.sh [RECORDS] [RUNS]   (5000000 3)
set -euo pipefail
records=${1:-5000000}; runs=${2:-3}
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin btx
btx=$PWD/target/release/btx
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 benches/repeat_btlog.py "$records" "$dir/L.btlog"
echo "machine load: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) cores; $records records, $(du -m "$dir/L.btlog" | cut -f1) MB"
median() { sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
time_of() {
  for _ in $(seq "$runs"); do
    /usr/bin/time -f '%e %M' -o "$dir/t" "$@" > /dev/null 2>&1
    cat "$dir/t"
  done > "$dir/all"
  echo "$(cut -d' ' -f1 "$dir/all" | median) $(cut -d' ' -f2 "$dir/all" | median)"
}
read -r cat_s cat_k < <(time_of cat "$dir/L.btlog")
read -r py_s py_k < <(time_of python3 benches/read_btlog.py "$dir/L.btlog")
read -r pyp_s pyp_k < <(time_of python3 benches/read_btlog.py "$dir/L.btlog" --print)
read -r node_s node_k < <(time_of "$btx" log "$dir/L.btlog" --node '#2')
read -r all_s all_k < <(time_of "$btx" log "$dir/L.btlog")
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
printf '%-34s %7s s %8s KB\n' "cat" "$cat_s" "$cat_k"
printf '%-34s %7s s %8s KB\n' "python reader, uid 2 counted" "$py_s" "$py_k"
printf '%-34s %7s s %8s KB\n' "python reader, every row printed" "$pyp_s" "$pyp_k"
printf '%-34s %7s s %8s KB  %sx the python reader\n' "btx log --node '#2'" "$node_s" "$node_k" "$(ratio "$node_s" "$py_s")"
printf '%-34s %7s s %8s KB  %sx the python reader printing\n' "btx log (every row)" "$all_s" "$all_k" "$(ratio "$all_s" "$pyp_s")"
