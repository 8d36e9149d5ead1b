#!/usr/bin/env python3
"""Runs behaviour trees in the real BehaviorTree.CPP (the PyPI package
behaviortreepy, BehaviorTree.CPP 4.8) with leaves scripted by a plan in the
fixture syntax (../shared/fixtures/btcpp/README.md, "Runner semantics"), and
records each run with the library's own FileLogger (.btlog) plus the wall
time of every tick, so that btx's executor can be compared with the library
transition for transition and tick for tick.

Usage: btcpp_run.py CASES.json OUT_DIR
CASES.json is a list of {"xml": ..., "plan": ..., "max_ticks": N} (and
"runs": K to tick the tree again after it completes, K runs in all). For case i
it writes OUT_DIR/i.btlog and OUT_DIR/i.json: {"ticks": [[start_us, end_us],
...], "root": "SUCCESS", "error": null}. Times are microseconds since the
epoch, as the FileLogger's are.
"""
import json
import os
import re
import sys
import time
import xml.etree.ElementTree as ET

import behaviortreepy as bt

STATUS = {"S": bt.NodeStatus.SUCCESS, "F": bt.NodeStatus.FAILURE}


def parse_plan(text):
    """key -> [(running_ticks, final_status)] in the fixture syntax."""
    plan = {}
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        key, _, rest = line.partition("=")
        outcomes = []
        for tok in rest.split(","):
            m = re.fullmatch(r"\s*(?:(\d+)[Rr])?([SFsf])\s*", tok)
            if not m:
                raise ValueError("not an outcome: %r" % tok)
            outcomes.append((int(m.group(1) or 0), STATUS[m.group(2).upper()]))
        plan[key.strip()] = outcomes
    return plan


class Leaves:
    """The plan's outcomes, one cursor per node fullPath (v4)."""

    def __init__(self, plan):
        self.plan = plan
        self.cursor = {}
        self.running = {}

    def outcome(self, node, ident, kind):
        keys = [node.full_path(), node.name(), ident,
                "@default_condition" if kind == "Condition" else "@default_action"]
        key = next((k for k in keys if k in self.plan), None)
        if key is None:
            return (0, bt.NodeStatus.SUCCESS)
        lst = self.plan[key]
        pos = self.cursor.get(node.full_path(), 0)
        self.cursor[node.full_path()] = pos + 1
        return lst[min(pos, len(lst) - 1)]

    def register(self, factory, ident, kind):
        if kind == "Condition":
            factory.register_simple_condition(
                ident, lambda node: self.outcome(node, ident, kind)[1])
            return

        def on_start(node):
            running, then = self.outcome(node, ident, kind)
            if running == 0:
                return then
            self.running[node.full_path()] = [running - 1, then]
            return bt.NodeStatus.RUNNING

        def on_running(node):
            left = self.running.get(node.full_path())
            if left is None:
                return bt.NodeStatus.SUCCESS
            if left[0] > 0:
                left[0] -= 1
                return bt.NodeStatus.RUNNING
            del self.running[node.full_path()]
            return left[1]

        def on_halted(node):
            self.running.pop(node.full_path(), None)

        factory.register_simple_stateful_action(ident, on_start, on_running, on_halted)


def leaf_models(xml):
    root = ET.fromstring(xml)
    out = []
    for model in root.iter("TreeNodesModel"):
        for child in model:
            if child.tag in ("Action", "Condition"):
                out.append((child.get("ID"), child.tag))
    return out


def run(case, log_path):
    factory = bt.BehaviorTreeFactory()
    leaves = Leaves(parse_plan(case["plan"]))
    for ident, kind in leaf_models(case["xml"]):
        leaves.register(factory, ident, kind)
    tree = factory.create_tree_from_text(case["xml"])
    logger = bt.FileLogger(tree, log_path)
    ticks = []
    root = "RUNNING"
    try:
        for _ in range(case.get("max_ticks", 100)):
            start = time.time_ns() // 1000
            status = tree.tick_exactly_once()
            ticks.append([start, time.time_ns() // 1000])
            root = status.name
            # A clear gap between ticks, so that each record falls in its
            # tick; timing cases set the period themselves.
            time.sleep(case.get("sleep_ms", 1.5) / 1000.0)
            # "runs": the tree is ticked again after it completes, as a
            # robot that does its job again does, until it has completed
            # that many times.
            if status != bt.NodeStatus.RUNNING:
                done = case.get("done", 0) + 1
                case["done"] = done
                if done >= case.get("runs", 1):
                    break
    finally:
        # FileLogger2 writes from a thread of its own: give it a moment
        # before the flush and the destructor that joins it.
        time.sleep(0.005)
        logger.flush()
        del logger
    return {"ticks": ticks, "root": root, "error": None}


def main():
    cases = json.load(open(sys.argv[1]))
    out = sys.argv[2]
    for i, case in enumerate(cases):
        log_path = os.path.join(out, "%d.btlog" % i)
        try:
            result = run(case, log_path)
        except Exception as e:  # the library refused the tree or threw
            result = {"ticks": [], "root": None, "error": str(e)}
        with open(os.path.join(out, "%d.json" % i), "w") as f:
            json.dump(result, f)


if __name__ == "__main__":
    main()
