"""Traces of a real run (docs/traces.md): the pcapng file (--pcap) holds one
packet per frame event, exactly as many of each kind, per node, as the
summary counts; tshark (when installed) reads the same comments; the SigMF
recording (--sigmf) of one node has every frame on the air annotated with the
outcome the trace gives it, and as many samples as the run had.

The run is slowed to 1/20 of real time and the frames meant to overlap on the
air (collision, half-duplex) are long (about 13 ms, 0.26 s of wall time), so
that two of them sent back to back by the test overlap even when a loaded
machine delays one of them by a good part of that."""

import glob
import json
import os
import shutil
import struct
import subprocess
import time
import unittest

from harness import BIN, LOSS_REASONS, Emulator, assert_accounted

TICK = 250
SLOW = ("--speed", "0.05", "--tick", str(TICK))
PAD = bytes(600)  # the overlapping frames' length (see above)
NODES = {1: (-5, 0, 10), 2: (0, 0, 10), 3: (5, 0, 10)}  # 1 and 3 equally far from 2
BSSID = bytes([0x02, 0x72, 0x66, 0x73, 0x69, 0x6C])
LLC_SNAP = bytes([0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00, 0x88, 0xB5])


def _options(buf):
    """pcapng options: [(code, value bytes)] up to opt_endofopt."""
    out, at = [], 0
    while at + 4 <= len(buf):
        code, length = struct.unpack_from("<HH", buf, at)
        if code == 0:
            break
        out.append((code, buf[at + 4:at + 4 + length]))
        at += 4 + (length + 3) // 4 * 4
    return out


def read_pcapng(path):
    """(info, packets): every block checked; packets as dicts with the
    timestamp (ns), the bytes, the comment and its key=value fields."""
    with open(path, "rb") as f:
        data = f.read()
    info = {"blocks": []}
    packets = []
    at = 0
    while at < len(data):
        btype, blen = struct.unpack_from("<II", data, at)
        assert blen % 4 == 0 and blen >= 12 and at + blen <= len(data), f"bad block at {at}"
        assert struct.unpack_from("<I", data, at + blen - 4)[0] == blen, "trailing length"
        body = data[at + 8:at + blen - 4]
        info["blocks"].append(btype)
        if btype == 0x0A0D0D0A:
            magic, major, minor = struct.unpack_from("<IHH", body, 0)
            assert (magic, major, minor) == (0x1A2B3C4D, 1, 0)
            for code, value in _options(body[16:]):
                if code == 1:
                    info["shb_comment"] = value.decode()
        elif btype == 1:
            info["link_type"], _, _ = struct.unpack_from("<HHI", body, 0)
            for code, value in _options(body[8:]):
                if code == 9:
                    info["tsresol"] = value[0]
        elif btype == 6:
            _, hi, lo, caplen, origlen = struct.unpack_from("<IIIII", body, 0)
            assert caplen == origlen
            pkt = body[20:20 + caplen]
            comment = ""
            for code, value in _options(body[20 + (caplen + 3) // 4 * 4:]):
                if code == 1:
                    comment = value.decode()
            words = comment.split()
            assert words and words[0] == "rfsitl", comment
            fields = dict(w.split("=", 1) for w in words[1:])
            packets.append({"ts": hi << 32 | lo, "data": pkt, "comment": comment, "f": fields})
        at += blen
    return info, packets


def decode_packet(pkt):
    """Radiotap fields and the 802.11 data frame's addresses and body."""
    version, _, rt_len, present = struct.unpack_from("<BBHI", pkt, 0)
    assert version == 0
    out = {"present": present}
    at = 8
    if present & 1:
        at = (at + 7) // 8 * 8
        out["tsft"] = struct.unpack_from("<Q", pkt, at)[0]
        at += 8
    if present & 2:
        out["flags"] = pkt[at]
        at += 1
    if present & 4:
        out["rate"] = pkt[at]
        at += 1
    if present & 0x20:
        out["signal"] = struct.unpack_from("<b", pkt, at)[0]
        at += 1
    if present & 0x40:
        out["noise"] = struct.unpack_from("<b", pkt, at)[0]
        at += 1
    assert at == rt_len, (at, rt_len)
    wlan = pkt[rt_len:]
    out["fc"] = wlan[0:2]
    out["addr1"], out["addr2"], out["addr3"] = wlan[4:10], wlan[10:16], wlan[16:22]
    out["seq"] = struct.unpack_from("<H", wlan, 22)[0] >> 4
    out["llc"] = wlan[24:32]
    out["payload"] = wlan[32:]
    return out


def mac(node_id):
    return b"\xff" * 6 if node_id == 255 else bytes([2, 0, 0, 0, 0, node_id])


def counts_by_node(packets):
    """Per node id: the summary's counters, counted from the trace."""
    nodes = {}
    for p in packets:
        f = p["f"]
        n = nodes.setdefault(int(f["node"]), {
            "handed_in": 0, "queue_dropped": 0, "transmitted": 0, "delivered": 0,
            "received": 0, "lost": {r: 0 for r in LOSS_REASONS}})
        if f["event"] == "lost":
            n["lost"][f["reason"]] += 1
        else:
            n[f["event"]] += 1
    return nodes


class TraceTest(unittest.TestCase):
    def check_counts(self, emu, packets):
        counted = counts_by_node(packets)
        for node_id in NODES:
            want = emu.node(node_id)
            got = counted.get(node_id)
            self.assertIsNotNone(got, f"node {node_id} has no events")
            for key in ("handed_in", "queue_dropped", "transmitted", "delivered", "received"):
                self.assertEqual(got[key], want[key], f"node {node_id} {key}")
            self.assertEqual(got["lost"], want["lost"], f"node {node_id} lost")

    def check_packets(self, info, packets, sent_payloads, fs):
        self.assertEqual(info["link_type"], 127)
        self.assertEqual(info["tsresol"], 9)
        self.assertEqual(info["blocks"][:2], [0x0A0D0D0A, 1])
        offset = int(info["shb_comment"].split("epoch_offset_s=")[1].split()[0])
        self.assertLess(abs(offset - time.time()), 600, "offset = wall clock at the start")
        handed_in = []
        for p in packets:
            f, d = p["f"], decode_packet(p["data"])
            sample = int(f["sample"])
            self.assertEqual(p["ts"], offset * 10**9 + round(sample * 1e9 / fs), p["comment"])
            self.assertEqual(d["tsft"], sample * 10**6 // int(fs))
            self.assertEqual(d["flags"], 0)
            self.assertNotIn("rate", d, "gmsk: no 802.11 rate")
            self.assertEqual("signal" in d, "snr_db" in f, p["comment"])
            self.assertEqual(d["noise"], -120)
            if "snr_db" in f:
                self.assertLessEqual(abs(d["signal"] - (float(f["snr_db"]) - 120)), 0.51)
            self.assertEqual(d["fc"], b"\x08\x00")
            self.assertEqual(d["addr1"], mac(int(f["dst"])))
            self.assertEqual(d["addr2"], mac(int(f["src"])))
            self.assertEqual(d["addr3"], BSSID)
            self.assertEqual(d["seq"], int(f["serial"], 16) & 0xFFF)
            self.assertEqual(d["llc"], LLC_SNAP)
            if f["event"] == "handed_in":
                handed_in.append((int(f["src"]), int(f["dst"]), d["payload"]))
            if f["event"] in ("transmitted", "delivered", "lost"):
                self.assertGreater(int(f["air_samples"]), 0)
        self.assertEqual(sorted(handed_in), sorted(sent_payloads))

    def check_tshark(self, path, packets):
        tshark = shutil.which("tshark")
        if tshark is None:
            print("tshark not installed: skipping its reading of the trace")
            return
        out = subprocess.run(
            [tshark, "-r", path, "-T", "fields", "-E", "separator=|",
             "-e", "frame.comment", "-e", "wlan.sa", "-e", "wlan.da", "-e", "radiotap.mactime",
             "-e", "llc.type"],
            capture_output=True, text=True, timeout=120, check=True,
            env=dict(os.environ, HOME=os.path.dirname(path)))
        rows = [line.split("|") for line in out.stdout.splitlines() if line]
        self.assertEqual([r[0] for r in rows], [p["comment"] for p in packets])
        for r, p in zip(rows, packets):
            d = decode_packet(p["data"])
            self.assertEqual(r[1], d["addr2"].hex(":"))
            self.assertEqual(r[2], d["addr1"].hex(":"))
            self.assertEqual(int(r[3]), d["tsft"])
            self.assertEqual(r[4], "0x88b5")
        # The display filter the docs suggest finds the collisions.
        out = subprocess.run(
            [tshark, "-r", path, "-Y", 'frame.comment contains "reason=collision"', "-T",
             "fields", "-e", "frame.number"],
            capture_output=True, text=True, timeout=120, check=True,
            env=dict(os.environ, HOME=os.path.dirname(path)))
        want = sum(1 for p in packets if p["f"].get("reason") == "collision")
        self.assertEqual(len(out.stdout.split()), want)

    def check_sigmf(self, sigmf_dir, node_id, packets, summary):
        fs = summary["sample_rate_hz"]
        meta_path = os.path.join(sigmf_dir, f"node{node_id}.sigmf-meta")
        data_path = os.path.join(sigmf_dir, f"node{node_id}.sigmf-data")
        with open(meta_path) as f:
            meta = json.load(f)
        with open(data_path, "rb") as f:
            raw = f.read()
        self.assertEqual(sorted(os.listdir(sigmf_dir)),
                         [f"node{node_id}.sigmf-data", f"node{node_id}.sigmf-meta"])
        g = meta["global"]
        self.assertEqual(g["core:datatype"], "cf32_le")
        self.assertEqual(g["core:sample_rate"], fs)
        self.assertEqual(g["core:version"], "1.0.0")
        self.assertEqual(g["core:num_channels"], 1)
        version = subprocess.run([BIN, "--version"], capture_output=True, text=True).stdout
        self.assertEqual(g["core:recorder"], version.strip())  # "rfsitl <version>"
        self.assertEqual(g["rfsitl:node_id"], node_id)
        self.assertFalse(g["rfsitl:truncated"])
        # The window covers the whole run: every sample the run had.
        run_samples = round(summary["virtual_s"] * fs)
        self.assertEqual(len(raw), 8 * run_samples)
        self.assertEqual(g["rfsitl:recorded_samples"], run_samples)
        self.assertEqual(meta["captures"], [{"core:sample_start": 0, "core:global_index": 0,
                                              "rfsitl:virtual_time_s": 0.0}])
        iq = struct.unpack(f"<{2 * run_samples}f", raw)
        power = [iq[2 * k] ** 2 + iq[2 * k + 1] ** 2 for k in range(run_samples)]

        # What the trace says of each frame, seen from node_id.
        expected = {}
        for p in packets:
            f = p["f"]
            serial = int(f["serial"], 16)
            if f["event"] == "transmitted":
                expected[serial] = {"start": int(f["sample"]), "len": int(f["air_samples"]),
                                    "outcome": "pending", "reason": None,
                                    "own": int(f["node"]) == node_id}
            elif f["event"] in ("delivered", "lost") and serial in expected:
                e = expected[serial]
                if e["outcome"] != "received":
                    e["outcome"], e["reason"] = f["event"], f.get("reason")
            elif f["event"] == "received" and int(f["node"]) == node_id:
                expected[serial]["outcome"], expected[serial]["reason"] = "received", None
        an = meta["annotations"]
        self.assertEqual(len(an), len(expected))
        self.assertEqual([a["core:sample_start"] for a in an],
                         sorted(a["core:sample_start"] for a in an))
        own_samples = [False] * run_samples
        for a in an:
            if a["rfsitl:own"]:
                for k in range(a["core:sample_start"], a["core:sample_start"] + a["core:sample_count"]):
                    own_samples[k] = True
        covered = [False] * run_samples
        outcomes = {}
        for a in an:
            e = expected[a["rfsitl:serial"]]
            start, count = a["core:sample_start"], a["core:sample_count"]
            self.assertEqual(start, e["start"])
            self.assertEqual(count, min(e["len"], run_samples - e["start"]))
            self.assertEqual(a["rfsitl:outcome"], e["outcome"], a)
            self.assertEqual(a.get("rfsitl:reason"), e["reason"], a)
            self.assertEqual(a["rfsitl:own"], e["own"])
            outcomes[a["rfsitl:outcome"]] = outcomes.get(a["rfsitl:outcome"], 0) + 1
            if e["own"]:
                # Zeros while it transmits. Only the ticks its transmission
                # fills are checked: in the tick where it ends, the engine
                # currently hands observers the samples after the transmission
                # at the tick's start instead of after the blanked part (see
                # docs/traces.md, "Known issues").
                self.assertEqual(start % TICK, 0, "frames start at tick boundaries")
                full = count // TICK * TICK
                self.assertEqual(max(power[start:start + full], default=0.0), 0.0,
                                 "blanked while it transmits")
            else:
                heard = [power[k] for k in range(start, start + count) if not own_samples[k]]
                if len(heard) >= 50:  # not hidden by this node's own transmission
                    self.assertGreater(sum(heard) / len(heard), 100.0, "a strong frame is there")
            for k in range(start, min(run_samples, start + count + 3000)):
                covered[k] = True
        # Elsewhere: the receiver's noise at unit power.
        quiet = [power[k] for k in range(run_samples) if not covered[k]]
        self.assertGreater(len(quiet), 10000)
        self.assertTrue(0.8 < sum(quiet) / len(quiet) < 1.25, sum(quiet) / len(quiet))
        # Counts agree with the summary for the recorded node.
        n = [x for x in summary["nodes"] if x["id"] == node_id][0]
        self.assertEqual(outcomes.get("received", 0), n["received"])
        self.assertEqual(sum(1 for a in an if a["rfsitl:own"]), n["transmitted"])
        self.assertEqual(len(an), sum(x["transmitted"] for x in summary["nodes"]))
        return outcomes

    def test_trace_and_recording_agree_with_the_summary(self):
        emu = Emulator(NODES, args=SLOW)
        pcap = os.path.join(emu.dir.name, "run.pcapng")
        sigmf = os.path.join(emu.dir.name, "iq")
        emu.args += ["--pcap", pcap, "--sigmf", sigmf, "--sigmf-nodes", "2",
                     "--sigmf-duration", "1000"]  # the whole run
        sent = []
        with emu:
            a1, a2, a3 = emu.agent(1), emu.agent(2), emu.agent(3)
            for i in range(2):  # 1 and 3 at once, equally strong at 2: collisions
                p1, p3 = b"collide one %d" % i + PAD, b"collide three %d" % i + PAD
                a1.send(1, 2, p1)
                a3.send(3, 2, p3)
                sent += [(1, 2, p1), (3, 2, p3)]
                self.assertEqual(a2.receive(1, timeout=0.5), [])
            a1.send(1, 2, b"hello two")
            sent.append((1, 2, b"hello two"))
            self.assertEqual(a2.receive(1), [(1, 2, b"hello two")])
            a2.send(2, 255, b"hello all")
            sent.append((2, 255, b"hello all"))
            self.assertEqual(a1.receive(1), [(2, 255, b"hello all")])
            self.assertEqual(a3.receive(1), [(2, 255, b"hello all")])
            p1, p2 = b"half duplex one" + PAD, b"half duplex two" + PAD
            a1.send(1, 2, p1)  # both transmit at once: neither hears the other
            a2.send(2, 1, p2)
            sent += [(1, 2, p1), (2, 1, p2)]
            self.assertEqual(a1.receive(1, timeout=0.5), [])
            self.assertEqual(a2.receive(1, timeout=0.5), [])
            emu.wait_settled()
            summary = emu.stop()
            assert_accounted(self, summary)
            self.assertGreaterEqual(emu.node(1)["lost"]["collision"], 1, emu.node(1))
            self.assertGreaterEqual(emu.node(2)["lost"]["half_duplex"], 1, emu.node(2))
            self.assertEqual(emu.node(2)["delivered"], 1, "the broadcast")

            info, packets = read_pcapng(pcap)
            written = [line for line in emu.output if line.startswith("rfsitl: pcap trace")]
            self.assertEqual(written, [f"rfsitl: pcap trace {pcap}: {len(packets)} frame events\n"])
            self.check_counts(emu, packets)
            self.check_packets(info, packets, sent, summary["sample_rate_hz"])
            self.check_tshark(pcap, packets)
            outcomes = self.check_sigmf(sigmf, 2, packets, summary)
            self.assertGreaterEqual(outcomes.get("received", 0), 1)
            self.assertGreaterEqual(outcomes.get("lost", 0), 1)

    def test_rotation_keeps_the_newest_files(self):
        emu = Emulator({1: (0, 0, 10), 2: (6, 0, 10)}, args=("--no-dashboard",))
        pcap = os.path.join(emu.dir.name, "rot.pcapng")
        emu.args += ["--pcap", pcap, "--pcap-max-mb", "0.004", "--pcap-files", "3"]
        limit = int(0.004 * 1024 * 1024)
        with emu:
            a1, a2 = emu.agent(1), emu.agent(2)
            for i in range(40):
                a1.send(1, 2, b"frame %03d " % i + bytes(100))
                self.assertEqual(len(a2.receive(1)), 1)
            summary = emu.stop()
            files = sorted(glob.glob(pcap + "*"))
            self.assertEqual(files, [pcap, pcap + ".1", pcap + ".2"])
            total = sum(n["handed_in"] + n["queue_dropped"] + n["transmitted"] + n["delivered"]
                        + n["received"] + sum(n["lost"].values()) for n in summary["nodes"])
            self.assertIn(f"rfsitl: pcap trace {pcap}: {total} frame events\n", emu.output)
            kept = []
            for f in (pcap + ".2", pcap + ".1", pcap):  # oldest first
                self.assertLessEqual(os.path.getsize(f), limit)
                info, packets = read_pcapng(f)
                self.assertEqual(info["blocks"][:2], [0x0A0D0D0A, 1])
                self.assertGreater(len(packets), 0)
                kept += packets
            self.assertLess(len(kept), total)
            payloads = [decode_packet(p["data"])["payload"][:10] for p in kept
                        if p["f"]["event"] == "handed_in"]
            self.assertIn(b"frame 039 ", payloads, "the newest frame is kept")
            self.assertNotIn(b"frame 000 ", payloads, "the oldest ones rotated away")
            serials = [int(p["f"]["serial"], 16) for p in kept if p["f"]["event"] == "transmitted"]
            self.assertEqual(serials, sorted(serials))
            self.assertEqual(serials[-1], 40)  # node index 0, its 40th frame (serials count from 1)


if __name__ == "__main__":
    unittest.main()
