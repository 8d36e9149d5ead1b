#!/usr/bin/env python3
"""A robot for btx's live tests: runs a tree in the real BehaviorTree.CPP
(the PyPI package behaviortreepy, 4.8) with leaves scripted by a plan in the
fixture syntax (as tests/oracle/btcpp_run.py does), publishing it with the
library's own Groot2Publisher and recording it with its own FileLogger.

Usage: robot.py TREE.xml PLAN PORT OUT.btlog [TICK_MS] [WAIT_MS] [MAX_TICKS] [RUNS]

It waits WAIT_MS before the first tick (for a client to start recording),
or, when WAIT_MS is "stdin", until a line comes on its standard input (the
test says when its client records); then ticks every TICK_MS until the root completes, RUNS times (1: a Nav2
robot's next goal is the tree ticked again, 300 ms later; the plan's
leaves go on with their scripts), then keeps publishing for a second so
that the last transitions can be fetched, and prints "DONE".
The Python leaves declare no ports, and BehaviorTree.CPP rejects an
attribute that is not a declared port, so the leaves' port attributes are
removed before loading: uids, names and transitions are unchanged.
"""
import os
import sys
import time
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "oracle"))
import btcpp_run  # noqa: E402
import behaviortreepy as bt  # noqa: E402


def without_leaf_ports(xml):
    root = ET.fromstring(xml)
    leaves = {ident for ident, _ in btcpp_run.leaf_models(xml)}
    for tree in root.iter("BehaviorTree"):
        for node in tree.iter():
            ident = node.get("ID") if node.tag in ("Action", "Condition") else node.tag
            if ident in leaves:
                for k in list(node.attrib):
                    if k not in ("ID", "name") and not k.startswith("_"):
                        del node.attrib[k]
    return ET.tostring(root, encoding="unicode")


def main():
    xml_path, plan_path, port, out = sys.argv[1:5]
    tick_ms = float(sys.argv[5]) if len(sys.argv) > 5 else 20
    wait = sys.argv[6] if len(sys.argv) > 6 else "1500"
    max_ticks = int(sys.argv[7]) if len(sys.argv) > 7 else 1000
    runs = int(sys.argv[8]) if len(sys.argv) > 8 else 1
    xml = without_leaf_ports(open(xml_path).read())
    factory = bt.BehaviorTreeFactory()
    leaves = btcpp_run.Leaves(btcpp_run.parse_plan(open(plan_path).read()))
    for ident, kind in btcpp_run.leaf_models(xml):
        leaves.register(factory, ident, kind)
    tree = factory.create_tree_from_text(xml)
    logger = bt.FileLogger(tree, out)
    publisher = bt.Groot2Publisher(tree, int(port))
    print("READY", flush=True)
    if wait == "stdin":
        sys.stdin.readline()
    else:
        time.sleep(float(wait) / 1000.0)
    for run in range(runs):
        if run > 0:
            time.sleep(0.3)
        for _ in range(max_ticks):
            status = tree.tick_exactly_once()
            time.sleep(tick_ms / 1000.0)
            if status != bt.NodeStatus.RUNNING:
                break
    time.sleep(1.0)
    logger.flush()
    del logger
    del publisher
    print("DONE", flush=True)


if __name__ == "__main__":
    main()
