#!/bin/sh
# Seeds each target's corpus with the project's own fixtures, then runs the
# targets one after another, RUNS executions each (default 10^6).
#   fuzz/run.sh                 every target
#   RUNS=100000 fuzz/run.sh db3 one target, fewer runs
set -eu
cd "$(dirname "$0")"
RUNS=${RUNS:-1000000}
seed() {
    t=$1
    shift
    mkdir -p "corpus/$t"
    cp "$@" "corpus/$t/"
    chmod u+w "corpus/$t"/*
}
seed btlog ../tests/fixtures/logs/*.btlog
seed fbl ../tests/fixtures/logs/*.fbl
seed db3 ../tests/fixtures/logs/*.db3
seed btcm ../tests/fixtures/btcm/*.json
seed session ../sessions/case-study.jsonl ../sessions/taxi*.jsonl ../sessions/kitting-lookat-fails-once.jsonl
targets=${*:-btlog fbl db3 btcm session}
for t in $targets; do
    echo "== $t: $RUNS runs"
    cargo fuzz run -s none "$t" -- -runs="$RUNS" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1
done
