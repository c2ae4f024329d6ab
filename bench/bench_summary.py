#!/usr/bin/env python3
"""Writes the benchmark's text summary (Markdown) from the CSV files in OUT.

    /usr/bin/python3 bench/bench_summary.py out/bench > out/bench/summary.md

The run's facts (QUICK or full, wall time, load average before it) come from
run_info.csv and the time per part from timings.csv, both written by the run.
"""

import argparse
import json
import datetime
import math
import os

import bench_common as bc


def fmt(v, digits=2, unit=""):
    return "n/a" if v is None or v != v else f"{v:.{digits}f}{unit}"


def ratio(paper, ours):
    return "n/a" if ours != ours or ours <= 0 else f"{paper / ours:.0f}x"


def met(ok):
    return "n/a" if ok is None else ("yes" if ok else "**no**")


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def fig4_stats(out):
    stats = {}
    for arch, path in bc.fig4_curves(out).items():
        rtts, lost = bc.read_rtts(path)
        stats[arch] = {"mean": bc.mean(rtts), "p10": bc.percentile(rtts, 0.1),
                       "p50": bc.percentile(rtts, 0.5), "p90": bc.percentile(rtts, 0.9),
                       "n": len(rtts), "lost": lost, "max_lag_ms": math.nan}
        summary = os.path.join(out, "fig4", f"summary_{arch}.json")
        if os.path.exists(summary):
            with open(summary) as f:
                stats[arch]["max_lag_ms"] = 1e3 * json.load(f).get("max_lag_s", math.nan)
    return stats


FIG4_NAMES = {"inprocess": "in-process (worker threads)",
              "split": "split (one `rfsitl node` process per node)",
              "gnuradio": "six GNU Radio flowgraphs (stock gr-digital GMSK)"}


def fig4_table(out, floor):
    f4 = fig4_stats(out)
    if not f4:
        return []
    lines = ["| architecture | pings | mean ms | p10 ms | p50 ms | p90 ms | mean / floor | lost "
             "| worst lag ms |", "|---|---|---|---|---|---|---|---|---|"]
    for arch in sorted(f4, key=lambda a: list(FIG4_NAMES).index(a) if a in FIG4_NAMES else 99):
        r = f4[arch]
        lines.append(f"| {FIG4_NAMES.get(arch, arch)} | {r['n'] + r['lost']} | {fmt(r['mean'])} | "
                     f"{fmt(r['p10'])} | {fmt(r['p50'])} | {fmt(r['p90'])} | "
                     f"{fmt(r['mean'] / floor)} | {r['lost']} | {fmt(r['max_lag_ms'], 1)} |")
    return lines


def capacity_verdict(rows):
    """(largest N keeping real time, its row, all smaller N kept it too)."""
    good = [r for r in rows if r["keeps_real_time"] == "1"]
    if not good:
        return None, None, False
    best = max(good, key=lambda r: int(r["n"]))
    below = [r for r in rows if int(r["n"]) < int(best["n"])]
    return int(best["n"]), best, all(r["keeps_real_time"] == "1" for r in below)


def headline(out, floor):
    f4 = fig4_stats(out)
    f5 = {int(r["n"]): r for r in bc.read_rows(os.path.join(out, "fig5_rtt_vs_n.csv"))}
    cap = bc.read_rows(os.path.join(out, "capacity.csv"))
    cap_fading = bc.read_rows(os.path.join(out, "capacity_fading.csv"))
    virt = bc.read_rows(os.path.join(out, "virtual_speed.csv"))
    mix = [r for r in bc.read_rows(os.path.join(out, "mix_kernel.csv")) if r["kind"] == "mix"]
    n6 = f4.get("inprocess", {}).get("mean", math.nan)
    n6_split = f4.get("split", {}).get("mean", math.nan)
    n6_gr = f4.get("gnuradio", {}).get("mean", math.nan)
    n15 = bc.num(f5[15]["mean_ms"]) if 15 in f5 else math.nan
    n15_p90 = bc.num(f5[15]["p90_ms"]) if 15 in f5 else math.nan
    x = lambda v: f" ({v / floor:.2f}x floor)" if v == v and floor == floor else ""  # noqa: E731
    lines = [
        "| measure | paper (12 vCPU) | rfsitl (this machine) | paper / rfsitl | issue target "
        "| met |",
        "|---|---|---|---|---|---|",
        f"| N = 6 mean RTT, one flowgraph / in-process | {bc.PAPER_N6_ONE_FLOWGRAPH_MS:.0f} ms | "
        f"{fmt(n6, 2, ' ms')}{x(n6)} | {ratio(bc.PAPER_N6_ONE_FLOWGRAPH_MS, n6)} | "
        f"<= {bc.TARGET_N6_MEAN_MS:.0f} ms | "
        f"{met(None if n6 != n6 else n6 <= bc.TARGET_N6_MEAN_MS)} |",
        f"| N = 6 mean RTT, split flowgraphs | {bc.PAPER_N6_SPLIT_MS:.0f} ms | "
        + (f"{fmt(n6_split, 2, ' ms')} (split) | {ratio(bc.PAPER_N6_SPLIT_MS, n6_split)}"
           if n6_split == n6_split else
           f"{fmt(n6, 2, ' ms')} (in-process; no split curve yet) | "
           f"{ratio(bc.PAPER_N6_SPLIT_MS, n6)}") + " | | |",
        f"| N = 6 mean RTT, six GNU Radio flowgraph nodes | {bc.PAPER_N6_SPLIT_MS:.0f} ms | "
        f"{fmt(n6_gr, 2, ' ms')} (stock gr-digital GMSK) | {ratio(bc.PAPER_N6_SPLIT_MS, n6_gr)} "
        "| | |",
        f"| N = 15 mean RTT | about {bc.PAPER_N15_SPLIT_MS:.0f} ms (split) | "
        f"{fmt(n15, 2, ' ms')}{x(n15)} | {ratio(bc.PAPER_N15_SPLIT_MS, n15)} | "
        f"<= {bc.TARGET_N15_MEAN_MS:.0f} ms | "
        f"{met(None if n15 != n15 else n15 <= bc.TARGET_N15_MEAN_MS)} |",
        f"| N = 15 p90 RTT | | {fmt(n15_p90, 2, ' ms')}{x(n15_p90)} | | "
        f"<= {bc.TARGET_N15_P90_MS:.0f} ms | "
        f"{met(None if n15_p90 != n15_p90 else n15_p90 <= bc.TARGET_N15_P90_MS)} |",
    ]
    for rows, what, target in ((cap, "", True),
                               (cap_fading, ", 4-tap Rician fading on every link", False)):
        if not rows:
            continue
        n_rt, row, monotone = capacity_verdict(rows)
        tested = ", ".join(r["n"] for r in rows)
        if n_rt is None:
            ours = f"none of N = {tested}"
        else:
            ours = (f"N = {n_rt} of {tested}: delivery ratio "
                    f"{fmt(bc.num(row['delivery_ratio']), 3)}, "
                    f"RTT p90 {fmt(bc.num(row['rtt_p90_ms']), 1)} ms, worst lag "
                    f"{fmt(bc.num(row['max_lag_ms']), 1)} ms"
                    f"{'' if monotone else ' (a smaller N failed)'}")
        goal = bc.TARGET_CAPACITY_N if target else bc.TARGET_CAPACITY_FADING_N
        lines.append(f"| real-time capacity, 1 ping/node/s{what} | not real time | {ours} | | "
                     f">= {goal} nodes | {met(n_rt is not None and n_rt >= goal)} |")
    for r in virt:
        if r.get("fading", "none") != "none" or r.get("multipath", "none") != "none":
            continue  # the flat channel's speed is the target's; the rest in their table
        s = bc.num(r["speed_x"])
        lines.append(f"| virtual-time speed, N = {r['nodes']}, 1 frame/node/s | | "
                     f"{fmt(s, 1, 'x real time')} | | >= {bc.TARGET_VIRTUAL_SPEED:.0f}x | "
                     f"{met(s >= bc.TARGET_VIRTUAL_SPEED) if r['nodes'] == '15' else 'n/a'} |")
    # At N >= 32 transmitters on the air the engine mixes receivers four at a
    # time (channel::mix_rows); below 24 one at a time (channel::mix).
    big = [bc.num(r["fraction_of_peak"]) for r in mix
           if int(r["n_inputs"]) >= 32 and r["name"] == "channel::mix_rows"]
    if big:
        lines.append(f"| mixing kernel (mix_rows), N >= 32, worst case | | "
                     f"{100 * min(big):.1f}% of peak | | "
                     f">= {100 * bc.TARGET_MIX_FRACTION:.0f}% | "
                     f"{met(min(big) >= bc.TARGET_MIX_FRACTION)} |")
    return lines


def fig5_table(out):
    rows = bc.read_rows(os.path.join(out, "fig5_rtt_vs_n.csv"))
    if not rows:
        return []
    lines = ["| N | mean ms | p10 ms | p90 ms | mean / floor | p90 / floor | lost | worst lag ms "
             "| late ticks |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['n']} | {fmt(bc.num(r['mean_ms']))} | {fmt(bc.num(r['p10_ms']))} | "
                     f"{fmt(bc.num(r['p90_ms']))} | {fmt(bc.num(r['mean_x_floor']))} | "
                     f"{fmt(bc.num(r['p90_x_floor']))} | {r['lost']}/{r['packets']} | "
                     f"{fmt(bc.num(r['max_lag_ms']))} | {r['late_ticks']} "
                     f"({fmt(100 * bc.num(r['late_tick_fraction']), 1)}%) |")
    return lines


def capacity_table(out, name="capacity"):
    rows = bc.read_rows(os.path.join(out, f"{name}.csv"))
    if not rows:
        return []
    lines = ["| N | real time | end lag ms | lag slope ms/s | worst lag ms | pings | "
             "delivery ratio | round trips | RTT mean ms | RTT p50 | RTT p90 | RTT p99 | "
             "lost: collision / half-duplex | CPU % of a core (per node) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['n']} | {'yes' if r['keeps_real_time'] == '1' else '**no**'} | "
            f"{fmt(bc.num(r['end_lag_ms']))} | {fmt(bc.num(r['lag_slope_ms_per_s']), 3)} | "
            f"{fmt(bc.num(r['max_lag_ms']), 1)} | {r['pings_sent']} | "
            f"{fmt(bc.num(r['delivery_ratio']), 3)} | {fmt(bc.num(r['round_trip_ratio']), 3)} | "
            f"{fmt(bc.num(r['rtt_mean_ms']))} | {fmt(bc.num(r['rtt_p50_ms']))} | "
            f"{fmt(bc.num(r['rtt_p90_ms']))} | {fmt(bc.num(r['rtt_p99_ms']))} | "
            f"{r['lost_collision']} / {r['lost_half_duplex']} | "
            f"{fmt(bc.num(r.get('cpu_percent', '')), 1)} "
            f"({fmt(bc.num(r.get('cpu_per_node_percent', '')), 2)}) |")
    return lines


def iperf_table(out, name):
    rows = [r for r in bc.read_rows(os.path.join(out, f"{name}.csv")) if "iperf_goodput_kbps" in r]
    if not rows:
        return []
    lines = ["| N | iperf3 UDP offered kbit/s | received kbit/s | lost % | jitter ms |",
             "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['n']} | {fmt(bc.num(r['iperf_offered_kbps']), 0)} | "
                     f"{fmt(bc.num(r['iperf_goodput_kbps']), 0)} | "
                     f"{fmt(bc.num(r['iperf_lost_percent']), 2)} | "
                     f"{fmt(bc.num(r['iperf_jitter_ms']), 2)} |")
    return lines


def virtual_table(out):
    rows = bc.read_rows(os.path.join(out, "virtual_speed.csv"))
    if not rows:
        return []
    lines = ["| N | channel | simulated s | wall s | speed | of flat | frames | delivered "
             "| receiver-ticks run / skipped |",
             "|---|---|---|---|---|---|---|---|---|"]
    flat = {}
    for r in rows:
        # Files of older runs have no fading or multipath column: a flat channel.
        fading, multipath = r.get("fading", "none"), r.get("multipath", "none")
        speed = bc.num(r["speed_x"])
        if fading == "none" and multipath == "none":
            flat[r["nodes"]] = speed
        channel = "flat" if fading == "none" and multipath == "none" else " + ".join(
            x for x in (multipath if multipath != "none" else "",
                        f"{fading} fading" if fading != "none" else "") if x)
        base = flat.get(r["nodes"])
        lines.append(f"| {r['nodes']} | {channel} | {fmt(bc.num(r['virtual_s']), 1)} | "
                     f"{fmt(bc.num(r['wall_s']))} | {fmt(speed, 1)}x | "
                     f"{fmt(speed / base if base else math.nan)} | "
                     f"{r['frames']} | {r['delivered']} | {r['receiver_ticks_run']} / "
                     f"{r['receiver_ticks_skipped']} |")
    return lines


def mix_table(out):
    rows = bc.read_rows(os.path.join(out, "mix_kernel.csv"))
    if not rows:
        return []
    peaks = [r for r in rows if r["kind"] == "peak"]
    lines = ["Peak (one thread): " + ", ".join(
        f"{p['name']} {fmt(bc.num(p['gflops']), 1)} Gflop/s = "
        f"{fmt(bc.num(p['cmac_per_s']) / 1e9)} G cMAC/s" for p in peaks) + ".", "",
        "| kernel | N inputs | block | G cMAC/s | fraction of peak |", "|---|---|---|---|---|"]
    for r in rows:
        if r["kind"] == "mix":
            lines.append(f"| {r['name']} | {r['n_inputs']} | {r['block']} | "
                         f"{fmt(bc.num(r['cmac_per_s']) / 1e9, 3)} | "
                         f"{fmt(100 * bc.num(r['fraction_of_peak']), 1)}% |")
    ramped = [r for r in rows if r["kind"] == "ramped"]
    if ramped:
        lines += ["", "The fading mixer (`channel::mix_ramped_add`: each coefficient ramps across "
                  "the block) beside its memory bound (reading the same inputs once, 8 bytes per "
                  "complex MAC) and its compute bound (four FMAs per vector and input: half the "
                  "peak):", "",
                  "| N inputs | block | G cMAC/s | memory bound G/s | of memory bound "
                  "| of compute bound |", "|---|---|---|---|---|---|"]
        compute = max(bc.num(p["cmac_per_s"]) for p in peaks) / 2
        for r in ramped:
            rate, bound = bc.num(r["cmac_per_s"]), bc.num(r["memory_bound_cmac_per_s"])
            lines.append(f"| {r['n_inputs']} | {r['block']} | {fmt(rate / 1e9, 2)} | "
                         f"{fmt(bound / 1e9, 2)} | {fmt(100 * rate / bound, 1)}% | "
                         f"{fmt(100 * rate / compute, 1)}% |")
    noise = [r for r in rows if r["kind"] == "noise" and r.get("samples_per_s")]
    if noise:
        lines += ["", "Receiver noise (counter-based Gaussian, one thread): " + ", ".join(
            f"B = {r['block']}: {fmt(bc.num(r['samples_per_s']) / 1e6, 1)} M samples/s "
            f"({fmt(1e9 / bc.num(r['samples_per_s']), 1)} ns/sample)" for r in noise) + "."]
    return lines


def dashboard_table(out):
    rows = bc.read_rows(os.path.join(out, "dashboard_cost.csv"))
    if not rows:
        return []
    base = bc.num(rows[0]["cpu_percent"])
    base_mem = bc.num(rows[0]["peak_rss_mb"])
    lines = ["| dashboard | emulator CPU % | vs off | peak RSS MB | vs off | per viewer KB/s "
             "| messages/s | worst lag ms |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        cpu, mem = bc.num(r["cpu_percent"]), bc.num(r["peak_rss_mb"])
        lines.append(f"| {r['mode']} | {fmt(cpu, 1)} | {cpu - base:+.1f} | {fmt(mem, 1)} | "
                     f"{mem - base_mem:+.1f} | {fmt(bc.num(r['ws_kbytes_per_s_per_viewer']), 0)} | "
                     f"{fmt(bc.num(r['ws_messages_per_s_per_viewer']), 1)} | "
                     f"{fmt(bc.num(r['worst_lag_ms']), 1)} |")
    return lines


def overload_lines(out):
    rows = bc.read_rows(os.path.join(out, "overload.csv"))
    if not rows:
        return []
    r = rows[0]
    lost = ", ".join(f"{k[5:].replace('_', ' ')} {r[k]}" for k in r if k.startswith("lost_"))
    return [f"{r['nodes']} nodes each offering {r['rate_per_node']} frames/s of "
            f"{r['payload_bytes']} bytes for {r['duration_s']} s, {r['idle_connections']} idle "
            f"connections, {r['viewers']} viewers (half never read)"
            f"{' (ASan build)' if r.get('asan') == '1' else ''}.", "",
            "| baseline RSS | at 10 s | at the end | peak | ceiling (baseline +) | held |",
            "|---|---|---|---|---|---|",
            f"| {r['baseline_rss_mb']} MB | {r['rss_10s_mb']} MB | {r['rss_end_mb']} MB | "
            f"{r['peak_rss_mb']} MB | {r['ceiling_mb']} MB | "
            f"{met(r['passed'] == '1')} |", "",
            f"Frames: offered {r['offered']}, handed in {r['handed_in']}, delivered "
            f"{r['delivered']}, lost {r['lost']} ({lost}), queue-dropped {r['queue_dropped']}, "
            f"to-agent dropped {r['to_agent_dropped']}; worst real-time lag "
            f"{fmt(bc.num(r['worst_lag_ms']), 0)} ms."]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    a = ap.parse_args()
    out = a.out
    info = {r["key"]: r["value"] for r in bc.read_rows(os.path.join(out, "run_info.csv"))}
    quick = info.get("quick", "?")
    wall_min = bc.num(info.get("wall_s")) / 60
    floor = bc.floor_ms(out)
    air = bc.read_rows(os.path.join(out, "airtime.csv"))
    p = []
    p.append("# rfsitl benchmark summary\n")
    info_path = os.path.join(out, "run_info.csv")
    when = os.path.getmtime(info_path) if os.path.exists(info_path) else None
    when = datetime.datetime.fromtimestamp(when) if when else datetime.datetime.now()
    p.append(f"{when.strftime('%Y-%m-%d %H:%M')}, {cpu_model()}, "
             f"{os.cpu_count()} cores; {'QUICK smoke run' if quick == '1' else 'full run'}, "
             f"{fmt(wall_min, 1)} min. GMSK at 1 Msps, 80-byte pings answered by 8-byte "
             "acks, ticks of 250 samples, real time unless noted, default formation "
             "(`rfsitl run --nodes N`), loopback TCP.\n")
    timings = []
    if os.path.exists(os.path.join(out, "timings.csv")):
        with open(os.path.join(out, "timings.csv")) as f:
            timings = [line.strip().split(",") for line in f if line.count(",") == 2]
    if timings:
        p.append("Time per part (1-minute load average at its end): "
                 + ", ".join(f"{k} {v} s ({ld})" for k, v, ld in timings)
                 + f"; load average before the run {info.get('load_before', '?')}. "
                 "Anything else running on these cores (a load average above about 1 before "
                 "the run) makes the real-time results worse than the emulator alone would "
                 "be.\n")
    if air:
        r = air[-1]
        p.append(f"**Air-time floor** (every case): {r['frame_samples']} + {r['ack_samples']} "
                 f"samples at {float(r['sample_rate_hz']) / 1e6:g} Msps = {fmt(floor, 3)} ms.\n")
    p.append("## Results beside the paper\n")
    p += headline(out, floor)
    p.append("")
    if fig4_table(out, floor):
        p.append("## RTT at N = 6 by architecture (Fig. 4 analogue; `fig4_rtt_cdf.png`)\n")
        p.append("Node 1 pings node 6 (80-byte frames, 8-byte acks); the paper's split figure, "
                 "150 ms, came from one GNU Radio flowgraph per node on 12 vCPUs. Worst lag: "
                 "the emulator's worst real-time lag during that run (six flowgraphs need more "
                 "than this machine's two cores to keep real time).\n")
        p += fig4_table(out, floor) + [""]
    if dashboard_table(out):
        p.append("## Dashboard cost (`dashboard_cost.csv`; bench/dashboard_cost.py)\n")
        p.append("A real-time run of the default formation under ping traffic (node 1 <-> "
                 "node N every 20 ms); each configuration a run of its own. Viewers are "
                 "WebSocket clients that watch a node (spectrum and constellation) and read "
                 "every snapshot.\n")
        p += dashboard_table(out) + [""]
    if overload_lines(out):
        p.append("## Bounded under overload (`overload.csv`; bench/overload.py)\n")
        p.append("Peak RSS of the emulator against a ceiling computed from its queue bounds "
                 "(the terms and their formulas are in the stage's output); held = peak <= "
                 "baseline + ceiling and every frame's books balance.\n")
        p += overload_lines(out) + [""]
    if fig5_table(out):
        p.append("## RTT against N (Fig. 5 analogue; `fig5_rtt_vs_n.csv`, `.png`)\n")
        p += fig5_table(out) + [""]
    if capacity_table(out):
        p.append("## Real-time capacity (`capacity.csv`, `capacity.png`)\n")
        p.append("Every node pings a random other node once per second (at a uniformly random "
                 "time within each second), and the destination answers each ping with an ack; "
                 f"{info.get('cap_seconds', '?')} s of real time. *Keeps real time*, from the emulator's own "
                 "stats lines (one per second) printed while the load was sending: the median "
                 "lag of the last 5 is under 50 ms, and the Theil-Sen slope of the lag over the "
                 "load is under 0.5 ms/s (no growth); definition in bench/bench_collect.py. "
                 "Delivery ratio = frames delivered / frames sent, pings and acks (frames still "
                 "queued 1 s after the last ping count as lost); round trips = pings acked "
                 "within 1 s. Loss reasons from the emulator's counters.\n")
        p += capacity_table(out) + [""]
    if capacity_table(out, "capacity_fading"):
        p.append("## Real-time capacity with fading (`capacity_fading.csv`)\n")
        p.append("The same load through the paper's path loss, the delay stage, four taps "
                 "100 ns and 3 dB apart and Rician fading (K = 6 dB) on every tap of every link "
                 "(`capacity_fading/scenario_N.yaml`).\n")
        p += capacity_table(out, "capacity_fading") + [""]
    if capacity_table(out, "ofdm_native"):
        p.append("## 802.11a/g at its native 20 Msps (`ofdm_native.csv`, `ofdm_native.png`)\n")
        p.append("The same load with OFDM at 24 Mbit/s, 20 Msps and ticks of "
                 f"{info.get('ofdm_tick', '?')} (`ofdm_native/scenario_N.yaml`). CPU: the "
                 "emulator's user + system time over the load, in % of one core.\n")
        p += capacity_table(out, "ofdm_native") + [""]
    if capacity_table(out, "ofdm_ip"):
        p.append("## 802.11a/g at 20 Msps with IP and iperf3 (`ofdm_ip.csv`)\n")
        p.append("The ofdm_native scenario with IP on every node (`ip: {enabled: true}`), the "
                 "same pings on the net ports and, for the whole load, iperf3 UDP (1472-byte "
                 "datagrams, 1500-byte IP packets) from node 1's namespace to node 2's.\n")
        p += capacity_table(out, "ofdm_ip") + [""] + iperf_table(out, "ofdm_ip") + [""]
    if virtual_table(out):
        p.append("## Virtual-time speed (`virtual_speed.csv`)\n")
        p += virtual_table(out) + [""]
    stage_rows = bc.read_rows(os.path.join(out, "stage_cost.csv"))
    if stage_rows:
        p.append("## Channel stages (`stage_cost.csv`)\n")
        p.append("Each stage on the channel alone (rfsitl_stage_cost: 16 nodes moving at 10 m/s, "
                 "4 on the air, 2.4 GHz, 1 Msps, one thread): the time a link adds per sample "
                 "(mixing, and the time-varying stages' grid), and per link recomputed when a "
                 "node moves.\n")
        p += ["| stage | model | ns per link and sample | ns per link update |",
              "|---|---|---|---|"]
        p += [f"| {r['stage']} | {r['model']} | {fmt(bc.num(r['ns_per_link_sample']))} | "
              f"{fmt(bc.num(r['ns_per_link_update']), 1)} |" for r in stage_rows]
        p.append("")
    rx_rows = bc.read_rows(os.path.join(out, "receiver_throughput.csv"))
    if rx_rows:
        p.append("## Receivers on one core (`receiver_throughput.csv`)\n")
        p.append("Each PHY's receive path fed 250-sample ticks on one core (rfsitl_receiver_"
                 "throughput): Msps of the thread's CPU time on unit-power noise and on 80-byte "
                 "frames back to back with 200-sample gaps at 30 dB SNR; median of 5 runs.\n")
        p += ["| PHY | noise [Msps] | with frames [Msps] | frames decoded |", "|---|---|---|---|"]
        p += [f"| {r['phy']} | {fmt(bc.num(r['noise_msps']), 1)} | "
              f"{fmt(bc.num(r['frames_msps']), 1)} | {r['decoded']}/{r['sent']} |"
              for r in rx_rows]
        p.append("")
    if mix_table(out):
        p.append("## Mixing kernel (`mix_kernel.csv`, `mix_kernel.png`)\n")
        p.append("channel::mix: one receiver, every input active; channel::mix_rows: N receivers "
                 "of the same N inputs (each receiver's own with coefficient 0), four at a time; "
                 "one thread; 1 complex MAC = 8 flops.\n")
        p += mix_table(out) + [""]
    print("\n".join(p))


if __name__ == "__main__":
    main()
