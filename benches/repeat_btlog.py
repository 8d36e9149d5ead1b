"""A .btlog of RECORDS transitions: the recorded kitting run repeated, each
repetition later than the last, as benches/logs.rs makes its big log.

    python3 benches/repeat_btlog.py RECORDS OUT           one file
    python3 benches/repeat_btlog.py RECORDS DIR RUNS      RUNS files in ten robots' directories

BTLOG names another recorded run to repeat.
"""
import os
import struct
import sys

records, out = int(sys.argv[1]), sys.argv[2]
runs = int(sys.argv[3]) if len(sys.argv) > 3 else None
src = open(os.environ.get("BTLOG", "tests/fixtures/logs/kitting_nominal.btlog"), "rb").read()
n = struct.unpack("<i", src[19:23])[0]
head, body = src[:31 + n], src[31 + n:]
recs = [(int.from_bytes(body[i:i + 6], "little"), body[i + 6:i + 9]) for i in range(0, len(body), 9)]
span = recs[-1][0] + 10_000
data = bytearray(head)
for k in range(records):
    rep, (dt, rest) = k // len(recs), recs[k % len(recs)]
    data += (dt + rep * span).to_bytes(8, "little")[:6] + rest
if runs is None:
    open(out, "wb").write(data)
else:
    for i in range(runs):
        d = os.path.join(out, f"robot-{i % 10}")
        os.makedirs(d, exist_ok=True)
        open(os.path.join(d, f"run-{i:05}.btlog"), "wb").write(data)
