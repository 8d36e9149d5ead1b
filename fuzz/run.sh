#!/bin/sh
# Seeds each target's corpus with the project's own fixtures, then runs the
# targets one after another, RUNS executions each (default 10^6), under the
# issue's bounds: a case over 1 s, an allocation over 256 MB or a resident
# size over 2 GB is a finding.
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
seed xml ../trees/*.xml ../tests/fixtures/*.xml ../tests/fixtures/answers/*.xml
seed plan ../trees/plans/*.plan ../tests/fixtures/answers/*.plan
seed domain ../trees/*.domain.toml
mkdir -p corpus/script corpus/keymap corpus/syntax
printf 'k := k + 1; s2 := s .. "x"; k > 2 ? "a" : "b"' > corpus/script/seed1
printf 'why = ["w"]\nquit = ["q", "Ctrl-c"]\n' > corpus/keymap/seed1
printf '1:3' > corpus/syntax/seed1
printf 'status(#3)' > corpus/syntax/seed2
targets=${*:-btlog fbl db3 btcm session xml plan domain script keymap syntax}
for t in $targets; do
    echo "== $t: $RUNS runs"
    cargo fuzz run -s none "$t" -- -runs="$RUNS" -timeout=1 -malloc_limit_mb=256 -rss_limit_mb=2048 -print_final_stats=1
done
