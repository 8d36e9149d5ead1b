#!/usr/bin/env bash
# Installs the BehaviorTree.CPP oracle of tests/oracle.rs: the PyPI package
# behaviortreepy (BehaviorTree.CPP 4.8) in a virtual environment under target/.
set -euo pipefail
cd "$(dirname "$0")/../.."
venv=target/oracle-venv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
if ! "$venv/bin/python" -c "import behaviortreepy" 2>/dev/null; then
  "$venv/bin/pip" install --quiet "behaviortreepy==0.1.4"
fi
"$venv/bin/python" -c "import behaviortreepy; print('oracle: behaviortreepy', behaviortreepy.__version__)"
