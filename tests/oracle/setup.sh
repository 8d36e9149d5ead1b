#!/usr/bin/env bash
# Installs the BehaviorTree.CPP oracle of tests/oracle.rs: the PyPI package
# behaviortreepy (BehaviorTree.CPP 4.8) in a virtual environment under target/.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=target/oracle-venv
if [ ! -x "$venv/bin/python" ]; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    # Debian's python3 has no venv module until python3-venv is installed.
    rm -rf "$venv"
    (apt-get update -qq && apt-get install -y -qq python3-venv python3-pip) >/dev/null 2>&1 || true
    python3 -m venv "$venv"
  fi
fi
if ! "$venv/bin/python" -c "import behaviortreepy" 2>/dev/null; then
  "$venv/bin/pip" install --quiet "behaviortreepy==0.1.4"
fi
# btview (a Groot2 client nobody here wrote) checks btx serve.
if ! "$venv/bin/python" -c "import btview" 2>/dev/null; then
  "$venv/bin/pip" install --quiet "btview==0.2.0"
fi
"$venv/bin/python" -c "import behaviortreepy; print('oracle: behaviortreepy', behaviortreepy.__version__)"
