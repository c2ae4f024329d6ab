"""Checks the fault tests (test_faults*.py) share: the books of a run frame by
frame from its pcap trace, the descriptors a process holds, and ending a run
with a chosen signal. Standard library only."""

import collections
import json
import os
import struct
import subprocess
import time

from harness import LOSS_REASONS

EPB = 6  # pcapng Enhanced Packet Block
OPT_COMMENT = 1


def pcap_events(path):
    """Every frame event of an rfsitl pcapng trace, in order, as the dict of its
    comment's fields ("rfsitl event=lost node=1 ... reason=collision"). A long
    flood rotates the trace (FILE.1 is older than FILE, FILE.2 older still):
    the rotated files are read first, oldest first."""
    rotated = []
    k = 1
    while os.path.exists(f"{path}.{k}"):
        rotated.insert(0, f"{path}.{k}")
        k += 1
    events = []
    for part in rotated + [path]:
        events += _file_events(part)
    return events


def _file_events(path):
    with open(path, "rb") as f:
        data = f.read()
    events = []
    at = 0
    while at + 12 <= len(data):
        block_type, block_len = struct.unpack_from("<II", data, at)
        if block_len < 12 or at + block_len > len(data):
            raise AssertionError(f"{path}: truncated pcapng block at byte {at}")
        if block_type == EPB:
            captured = struct.unpack_from("<I", data, at + 20)[0]
            opt = at + 28 + ((captured + 3) & ~3)
            comment = None
            while opt + 4 <= at + block_len - 4:
                code, length = struct.unpack_from("<HH", data, opt)
                if code == 0:
                    break
                if code == OPT_COMMENT:
                    comment = data[opt + 4:opt + 4 + length].decode()
                opt += 4 + ((length + 3) & ~3)
            if comment is None or not comment.startswith("rfsitl "):
                raise AssertionError(f"{path}: packet without an rfsitl comment at byte {at}")
            events.append(dict(field.split("=", 1) for field in comment.split()[1:]))
        at += block_len
    return events


def check_every_frame(test, events, summary):
    """Frame by frame from the trace, per node: every frame handed in was
    dropped by the full queue, is still queued, or went on the air; every frame
    on the air has at most one outcome (a loss with its reason), and the ones
    without an outcome are exactly the summary's pending frames that are not
    queued. The trace's counts equal the summary's counters. Returns
    {serial: (transmitted event, outcome event or None)}."""
    counts = collections.Counter((e["event"], int(e["node"])) for e in events)
    frames = {}
    for e in events:
        serial = int(e.get("serial", "0"), 16)
        if e["event"] == "transmitted":
            test.assertNotIn(serial, frames, f"serial {serial:#x} went on the air twice")
            frames[serial] = [e, None]
        elif e["event"] in ("delivered", "lost"):
            test.assertIn(serial, frames, f"an outcome for a frame never on the air: {e}")
            first = frames[serial][1]
            test.assertIsNone(first, f"a second outcome: {e}, the first: {first}")
            if e["event"] == "lost":
                test.assertIn(e.get("reason"), LOSS_REASONS, f"a loss without a reason: {e}")
            frames[serial][1] = e
    lost = collections.Counter((int(e["node"]), e["reason"])
                               for e in events if e["event"] == "lost")
    for n in summary["nodes"]:
        nid = n["id"]
        for kind in ("handed_in", "queue_dropped", "transmitted", "delivered"):
            test.assertEqual(counts[(kind, nid)], n[kind], f"node {nid}: {kind} events vs counter")
        for reason in LOSS_REASONS:
            test.assertEqual(lost[(nid, reason)], n["lost"][reason], f"node {nid}: lost {reason}")
        test.assertEqual(n["handed_in"], n["queue_dropped"] + n["queue_depth"] + n["transmitted"],
                         f"node {nid}: a frame handed in neither dropped, queued nor sent: {n}")
        unsettled = sum(1 for tx, out in frames.values() if int(tx["node"]) == nid and out is None)
        test.assertEqual(n["pending"], n["queue_depth"] + unsettled,
                         f"node {nid}: pending is not queued + on the air: {n}")
    return {serial: tuple(v) for serial, v in frames.items()}


def frames_overlapping(frames, node_id, t0, t1, sample_rate_hz=1e6):
    """Frames node_id had on the air at some time in [t0, t1] (virtual
    seconds), from check_every_frame's result."""
    out = []
    for tx, outcome in frames.values():
        if int(tx["node"]) != node_id:
            continue
        start = float(tx["t"])
        end = start + int(tx["air_samples"]) / sample_rate_hz
        if start <= t1 and end >= t0:
            out.append((tx, outcome))
    return out


def fd_count(pid):
    """Descriptors the process holds now."""
    return len(os.listdir(f"/proc/{pid}/fd"))


def node_in(report, node_id):
    return next(n for n in report["nodes"] if n["id"] == node_id)


def wait_settled(emu, timeout=60.0):
    """Waits until no node has a frame without its outcome (nothing queued or
    on the air), so that the summary must balance with pending = 0."""
    return emu.wait_until(lambda st: all(n["pending"] == 0 for n in st["nodes"]),
                          timeout=timeout, what="every frame settled")


def end_with_signal(emu, sig, timeout=60.0):
    """Ends the run with `sig` (the harness stops with SIGINT): returns its exit
    status and loads the summary it wrote into emu.summary."""
    emu.proc.send_signal(sig)
    try:
        rc = emu.proc.wait(timeout)
    except subprocess.TimeoutExpired:
        emu.proc.kill()
        emu.proc.wait(10)
        raise AssertionError(f"emulator did not exit within {timeout} s of signal {sig}")
    emu._reader.join(10)
    emu.proc.stdout.close()
    with open(emu.summary_path) as f:
        emu.summary = json.load(f)
    return rc


def wait_for(predicate, timeout, what):
    """Polls predicate() until it holds; `what` (text, or a function giving it
    at the time of failure) names it in the error after `timeout` s."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out waiting for {what() if callable(what) else what}")
        time.sleep(0.02)


def count_lines(emu, text):
    return sum(text in line for line in list(emu.output))

