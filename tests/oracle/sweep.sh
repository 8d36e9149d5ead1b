#!/usr/bin/env bash
# The differential sweep against BehaviorTree.CPP: 10^4 generated trees (or
# $CASES, from seed $SEED), btx's executor against the real library.
set -euo pipefail
cd "$(dirname "$0")/../.."
BTX_ORACLE_CASES="${CASES:-10000}" BTX_ORACLE_SEED="${SEED:-0}" \
  cargo test --release --test oracle -- --nocapture
