#!/usr/bin/python3
"""A closed loop in virtual time: a Python controller keeps a three-hop chain
connected while its far end flies away.

Node 1 (a ground station) sends a frame to node 4 (a UAV flying away along x
at 5 m/s) every 100 ms of virtual time; nodes 2 and 3 are relays, and this
script is every node's agent: a frame that node 2 decodes goes on to node 3,
then to node 4. Every 100 ms the controller reads the link table and moves
the relays so that the three hops stay equal (with --no-control they stay
where they started). The channel is the paper's (SNR falls 60 dB a decade of
distance) with the noise at -130 dB, so a fixed chain breaks at its last hop;
the MAC is CSMA with ACKs, so that a relay forwarding one frame and the
ground station sending the next take turns.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/relay_control.py
    ... relay_control.py --no-control      # the same flight without the controller
    ... relay_control.py --plot relay.png  # the weakest hop's SNR and the deliveries

It prints, each 5 s of virtual time, the far node's distance, every hop's SNR
and the end-to-end delivery ratio so far.
"""

import argparse
import struct

import rfsitl

ALTITUDE = 20.0
SPEED = 5.0        # m/s, node 4 along x
PERIOD = 0.1       # s: the controller's and the traffic's period


def scenario(duration_s, seed):
    return rfsitl.scenario_from_dict({
        "name": "relay-control",
        "seed": seed,
        "time": {"mode": "virtual", "duration_s": duration_s},
        "channel": {"noise_power_db": -130},
        "mac": {"type": "csma"},
        "nodes": [{"id": i, "position": {"x": x, "y": 0, "z": ALTITUDE}}
                  for i, x in ((1, 0.0), (2, 10.0), (3, 20.0), (4, 30.0))],
    })


def hop_snrs(emu):
    links = emu.links()
    snr = {}
    for tx, rx in ((1, 2), (2, 3), (3, 4)):
        row = links[(links["tx"] == tx) & (links["rx"] == rx)]
        snr[(tx, rx)] = float(row["snr_db"].iloc[0])
    return snr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=40.0, help="virtual seconds")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-control", action="store_true", help="leave the relays where they are")
    ap.add_argument("--plot", help="write a PNG of the weakest hop's SNR and the deliveries")
    args = ap.parse_args()

    emu = rfsitl.Emulator(scenario(args.duration + 1.0, args.seed))
    next_hop = {2: 3, 3: 4}
    sent = arrived = 0
    series = []  # (t, far distance, weakest hop SNR, arrived so far / sent so far)
    while emu.now < args.duration:
        t = emu.now
        far = 30.0 + SPEED * t
        emu.set_position(4, (far, 0.0, ALTITUDE))
        if not args.no_control:
            emu.set_position(2, (far / 3.0, 0.0, ALTITUDE))
            emu.set_position(3, (2.0 * far / 3.0, 0.0, ALTITUDE))
        # The ground station's frame, numbered; relays forward what they decode.
        emu.send(1, 2, struct.pack("<I", sent) + bytes(40))
        sent += 1
        emu.run_for(PERIOD)
        for _, _, node, payload, _ in emu.received():
            if node in next_hop:
                emu.send(node, next_hop[node], payload)
            elif node == 4:
                arrived += 1
        snr = hop_snrs(emu)
        series.append((emu.now, far, min(snr.values()), arrived / sent))
        if round(emu.now / PERIOD) % 50 == 0:
            hops = "  ".join(f"{a}->{b} {v:5.1f} dB" for (a, b), v in snr.items())
            print(f"t={emu.now:5.1f} s  far={far:5.1f} m  {hops}  delivered {arrived}/{sent}")
    emu.finish()
    print(f"end to end: {arrived} of {sent} frames ({100.0 * arrived / sent:.1f} %), "
          f"controller {'off' if args.no_control else 'on'}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (a, b) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        a.plot([s[0] for s in series], [s[2] for s in series])
        a.set_ylabel("weakest hop SNR (dB)")
        b.plot([s[0] for s in series], [s[3] for s in series])
        b.set_ylabel("delivered (fraction)")
        b.set_xlabel("virtual time (s)")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
