"""rfsitl from Python: scenarios, runs in virtual time driven step by step,
real-time runs with their ports, and the registered components.

    import rfsitl
    sc = rfsitl.load_scenario("scenarios/six_uav.yaml")
    emu = rfsitl.Emulator(sc)
    emu.run_for(2.0)
    print(emu.counters())        # a pandas DataFrame, one row per node
    print(emu.links())           # distance, gain, SNR and PER estimate per link

A thin layer over the C++ engine (the native module _rfsitl): the same
scenario reader and errors as `rfsitl run`, the same Session that assembles
its runs. Tables are pandas DataFrames when pandas is installed (Debian:
python3-pandas), else dicts of NumPy arrays.
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _rfsitl
from ._paths import PLUGINS_FROM_PACKAGE

try:  # pandas is optional: tables fall back to dicts of arrays
    import pandas as _pd
except ImportError:  # pragma: no cover - depends on the machine
    _pd = None

__all__ = [
    "Scenario", "ScenarioError", "RunError", "Emulator", "RealTimeRun",
    "load_scenario", "scenario_from_yaml", "scenario_from_dict", "components", "version",
    "BROADCAST",
]

Scenario = _rfsitl.Scenario
#: A scenario that cannot be used; the message names file:line:key (or, for a
#: dict, the key's path in it), as `rfsitl run` does. A ValueError.
ScenarioError = _rfsitl.ScenarioError
#: A run that could not be assembled or failed while running. A RuntimeError.
RunError = _rfsitl.RunError
#: The destination id that every node receives.
BROADCAST = 255

_EVENT_KINDS = _rfsitl.event_kinds()
_LOSS_REASONS = _rfsitl.loss_reasons()


def _load_plugins() -> None:
    """Plugins as the rfsitl program loads them: RFSITL_PLUGIN_PATH, then the
    installed plugin folder beside this package (none in a build tree)."""
    installed = ""
    if PLUGINS_FROM_PACKAGE:
        installed = os.path.normpath(os.path.join(os.path.dirname(__file__), PLUGINS_FROM_PACKAGE))
    for path, error in _rfsitl.load_plugins(installed):
        import warnings
        warnings.warn(f"rfsitl: plugin {path} skipped: {error}", RuntimeWarning, stacklevel=2)


_load_plugins()


def version() -> str:
    """The build's version, as `rfsitl --version` prints it."""
    return _rfsitl.version()


def load_scenario(path: Union[str, os.PathLike]) -> Scenario:
    """Reads a scenario file, as `rfsitl run FILE` does."""
    return Scenario.load(os.fspath(path))


def scenario_from_yaml(text: str, source: str = "<yaml>") -> Scenario:
    """Reads a scenario from YAML text; errors name `source`:line:key."""
    return Scenario.from_yaml(text, source)


def scenario_from_dict(document: Mapping[str, Any], source: str = "dict",
                       base_dir: Union[str, os.PathLike] = "") -> Scenario:
    """Reads a scenario given as nested dicts and lists, with a file's rules:
    strings are text, numbers and booleans values (a string "5" is not a
    number). Errors name the key's path, e.g. "dict: nodes[1].phy.type:
    unknown 'gmskk' (known: ...)". Relative data files (traces, antenna
    patterns) are taken from `base_dir` (default: the working folder)."""
    try:
        text = json.dumps(document, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise ScenarioError(f"{source}: not a document of dicts, lists, strings, numbers and "
                            f"booleans: {e}") from None
    return Scenario.from_json(text, source, os.fspath(base_dir))


def components(kind: Optional[str] = None) -> List[Dict[str, Any]]:
    """Every registered component (PHYs, MACs, channel stages, position sources,
    mobility models, the radio) with its declared settings: what `rfsitl
    describe` prints, as a list of dicts {kind, name, doc, settings: [{name,
    type, default, unit, limits, choices, doc}]}."""
    all_ = json.loads(_rfsitl.components_json())
    return [c for c in all_ if kind is None or c["kind"] == kind]


def _table(columns: Dict[str, Any], index: Optional[str] = None):
    if _pd is None:
        return columns
    frame = _pd.DataFrame(columns, copy=False)
    return frame.set_index(index) if index else frame


def _as_scenario(scenario: Union[Scenario, str, os.PathLike, Mapping[str, Any]]) -> Scenario:
    if isinstance(scenario, Scenario):
        return scenario
    if isinstance(scenario, Mapping):
        return scenario_from_dict(scenario)
    return load_scenario(scenario)


class Emulator:
    """A run in virtual time, advanced step by step from Python.

    Between steps the caller may move nodes (set_position), hand in frames
    (send), and read what happened (counters, links, events, received, iq).
    Outcomes depend only on the scenario, its seed and what the caller did at
    which tick: the same calls give the same results, bit for bit.

    The scenario's time.duration_s ends the run (advance stops there); the
    caller is every node's agent: decoded frames are kept as "received" events
    (keep_frames=False counts them as to_agent_dropped instead, as `rfsitl run`
    does with no agent connected, so that both give the same counters).
    With record_events=False and iq=False nothing watches the engine (no
    events(), received() or tap()): a run then costs what `rfsitl run` costs.
    """

    def __init__(self, scenario: Union[Scenario, str, os.PathLike, Mapping[str, Any]], *,
                 keep_frames: bool = True, record_events: bool = True, iq: bool = True,
                 max_events: int = 1_000_000, max_tap_samples: int = 1 << 24,
                 pcap: Optional[str] = None, sigmf: Optional[str] = None):
        self.scenario = _as_scenario(scenario)
        self._run = _rfsitl.VirtualRun(self.scenario, keep_frames, record_events, iq, max_events,
                                       max_tap_samples, pcap or "", sigmf or "")
        self._events: List[Dict[str, Any]] = []
        self._summary: Optional[Dict[str, Any]] = None

    # ---- time ----

    @property
    def now(self) -> float:
        """Virtual seconds emulated so far."""
        return self._run.now_s

    @property
    def tick(self) -> float:
        """One tick's length in seconds (the engine's step)."""
        return self._run.tick_s

    @property
    def end(self) -> float:
        """The scenario's duration in seconds (0: none)."""
        return self._run.end_s

    @property
    def done(self) -> bool:
        """The scenario's duration has been emulated (or finish() was called)."""
        return self._run.finished or (self.end > 0 and self.now >= self.end - 1e-12)

    @property
    def node_ids(self) -> List[int]:
        return self._run.node_ids

    def step(self, ticks: int = 1) -> float:
        """Runs `ticks` ticks; returns the virtual time reached."""
        if ticks < 0:
            raise ValueError(f"ticks must be >= 0, got {ticks}")
        return self._advance(self.now + ticks * self.tick)

    def run_for(self, seconds: float) -> float:
        """Runs `seconds` of virtual time (whole ticks); returns the time reached."""
        if seconds < 0:
            raise ValueError(f"seconds must be >= 0, got {seconds}")
        return self._advance(self.now + seconds)

    def run_until(self, condition: Union[float, Callable[["Emulator"], bool]], *,
                  step_s: float = 0.1, timeout_s: Optional[float] = None) -> bool:
        """Runs until virtual time `condition` (a number), or until
        `condition(self)` is true, checked after every step of `step_s`
        virtual seconds. True if the condition was met; False if the run
        ended first or `timeout_s` virtual seconds passed."""
        if not callable(condition):
            self._advance(float(condition))
            return self.now >= float(condition) - 1e-12
        if step_s <= 0:
            raise ValueError(f"step_s must be > 0, got {step_s}")
        start = self.now
        while not condition(self):
            if self.done or (timeout_s is not None and self.now - start >= timeout_s):
                return False
            self._advance(self.now + step_s)
        return True

    def run(self) -> Dict[str, Any]:
        """Runs to the scenario's end and returns the summary (finish())."""
        if self.end <= 0:
            raise RunError("the scenario has no duration (time.duration_s 0): use run_for()")
        self._advance(self.end)
        return self.finish()

    def _advance(self, until: float) -> float:
        return self._run.advance(until)

    # ---- acting between steps ----

    def send(self, src: int, dst: int, payload: bytes) -> bool:
        """Hands a frame from node `src` to its TX queue, for node `dst`
        (BROADCAST: every node). False if the queue was full (counted as
        queue_dropped). ValueError if larger than the node's frames allow."""
        try:
            return self._run.send(src, dst, bytes(payload))
        except IndexError as e:
            raise KeyError(str(e)) from None

    def set_position(self, node: int, xyz: Optional[Sequence[float]] = None, *,
                     geodetic: Optional[Sequence[float]] = None,
                     velocity: Optional[Sequence[float]] = None,
                     attitude: Optional[Sequence[float]] = None) -> None:
        """Moves node `node` from the next tick: `xyz` local east/north/up
        metres from the scenario's origin, or `geodetic` (lat deg, lon deg,
        alt m); optionally its velocity (east/north/up m/s, for Doppler and
        fading) and attitude (roll, pitch, yaw rad, for antennas). A node that
        follows a mobility model goes back to it at the model's next update."""
        self._run.report(node, local=_triple(xyz), geodetic=_triple(geodetic),
                         velocity=_triple(velocity), attitude=_triple(attitude))

    # ---- reading ----

    def counters(self):
        """Every node's counters (the summary's, one row per node id)."""
        names, table = self._run.counters()
        ids = np.asarray(self.node_ids, dtype=np.uint8)
        if _pd is not None:  # one block: no copy, no column by column assembly
            return _pd.DataFrame(table, index=_pd.Index(ids, name="node"), columns=names,
                                 copy=False)
        columns = {"node": ids}
        for j, name in enumerate(names):
            columns[name] = table[:, j]
        return columns

    def links(self, payload_bytes: int = 80):
        """Every ordered pair (tx, rx): distance (m), path gain (dB, fading
        included), SNR (dB over the noise in the sample bandwidth) and the
        receiver PHY's declared PER estimate for `payload_bytes` at that SNR
        (what `rfsitl links` shows). NaN where there is no link or estimate."""
        return _table(self._run.links(payload_bytes))

    def positions(self):
        """Every node's local east/north/up position (m), N x 3 (NaN: unknown)."""
        return self._run.positions()

    def events(self):
        """The frame events since the last call (handed_in, queue_dropped,
        transmitted, received, delivered, lost), oldest first: time_s, kind,
        node (where it happened), src, dst, serial, length_samples, snr_db,
        reason (lost only), retry, payload. Taken: a second call gives newer
        ones only. See also received()."""
        self._collect()
        taken, self._events = self._events, []
        return _events_table(taken)

    def received(self, node: Optional[int] = None) -> List[Tuple[float, int, int, bytes, float]]:
        """Frames decoded (and kept) since the last call, as (time_s, src,
        receiver, payload, snr_db) tuples; only node `node`'s if given. Taken,
        like events(); the other events stay for events()."""
        self._collect()
        out, rest = [], []
        for chunk in self._events:
            kinds = chunk["kind"]
            mine = kinds == _EVENT_KINDS.index("received")
            if node is not None:
                mine &= chunk["node"] == node
            for i in np.flatnonzero(mine):
                out.append((float(chunk["time_s"][i]), int(chunk["src"][i]), int(chunk["node"][i]),
                            chunk["payload"][i], float(chunk["snr_db"][i])))
            keep = np.flatnonzero(~mine)
            if len(keep):
                rest.append({k: ([v[i] for i in keep] if k == "payload" else v[keep])
                             for k, v in chunk.items()})
        self._events = rest
        return out

    def _collect(self) -> None:
        chunk = self._run.take_events()
        if len(chunk["kind"]):
            self._events.append(chunk)

    @property
    def events_dropped(self) -> int:
        """Events left out because max_events were waiting unread."""
        return self._run.events_dropped

    def tap(self, node: int, on: bool = True) -> None:
        """Records node `node`'s received samples from the next step on (iq())."""
        self._run.set_tap(node, on)

    def iq(self, node: int) -> Tuple[float, np.ndarray]:
        """Node `node`'s received samples of the latest step (tap() first): the
        virtual time of the first one and a complex64 array (the receiver's
        front-end scale: noise of unit power; zeros while its own transmitter
        blanked it). At most max_tap_samples, the latest ones."""
        first_s, samples, _cut = self._run.take_samples(node)
        return first_s, samples

    def finish(self) -> Dict[str, Any]:
        """Ends the run and returns its summary: the document `rfsitl run
        --summary-json` writes. Idempotent; no step after it."""
        if self._summary is None:
            self._summary = json.loads(self._run.finish())
        return self._summary

    summary = finish


class RealTimeRun:
    """A real-time run with its ports, as `rfsitl run` serves it (net ports,
    location ports, live position sources; ip=True as --ip, which needs root),
    started and stopped from Python. Use as a context manager:

        with rfsitl.RealTimeRun(sc) as run:
            ...                      # agents connect to run.net_port(node)
        print(run.summary["nodes"])
    """

    def __init__(self, scenario: Union[Scenario, str, os.PathLike, Mapping[str, Any]], *,
                 ip: bool = False, dashboard: bool = False,
                 dashboard_port: Optional[int] = None, pcap: Optional[str] = None):
        self.scenario = _as_scenario(scenario)
        self._run = _rfsitl.RealTimeRun(self.scenario, ip, dashboard, dashboard_port, pcap or "")
        self.summary: Optional[Dict[str, Any]] = None

    def start(self) -> "RealTimeRun":
        """Opens every port and starts the clock."""
        self._run.start()
        return self

    def net_port(self, node: int) -> Tuple[str, int]:
        """(address, port) of node `node`'s net port."""
        return self._run.bind_address, self._run.net_base + 10 * node

    @property
    def dashboard_port(self) -> Optional[int]:
        return self._run.dashboard_port

    @property
    def running(self) -> bool:
        return self._run.running

    @property
    def now(self) -> float:
        """Virtual seconds emulated so far (the wall clock's, times the speed)."""
        return self._run.virtual_s

    @property
    def max_lag(self) -> float:
        """The worst lag behind the wall clock so far, seconds."""
        return self._run.max_lag_s

    def wait(self, timeout_s: float) -> bool:
        """Waits up to `timeout_s` for the run's end; True if it ended."""
        return self._run.wait(timeout_s)

    def stop(self) -> Dict[str, Any]:
        """Stops the run and returns its summary (idempotent)."""
        if self.summary is None:
            self.summary = json.loads(self._run.stop())
        return self.summary

    def __enter__(self) -> "RealTimeRun":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()


def _triple(v: Optional[Sequence[float]]) -> Optional[Tuple[float, float, float]]:
    if v is None:
        return None
    t = tuple(float(x) for x in v)
    if len(t) != 3:
        raise ValueError(f"expected three numbers, got {len(t)}")
    return t


def _events_table(chunks: Iterable[Dict[str, Any]]):
    chunks = list(chunks)
    if chunks:
        columns = {k: (sum((c[k] for c in chunks), []) if k == "payload"
                       else np.concatenate([c[k] for c in chunks]))
                   for k in chunks[0]}
    else:
        columns = _rfsitl_empty_events()
    kinds = columns["kind"]
    reasons = columns["reason"]
    if _pd is not None:
        columns["kind"] = _pd.Categorical.from_codes(kinds.astype(np.int64), _EVENT_KINDS)
        columns["reason"] = _pd.Categorical.from_codes(reasons.astype(np.int64), _LOSS_REASONS)
    else:
        columns["kind"] = np.asarray(_EVENT_KINDS, dtype=object)[kinds] if len(kinds) else kinds
    return _table(columns)


def _rfsitl_empty_events() -> Dict[str, Any]:
    return {"time_s": np.zeros(0), "kind": np.zeros(0, np.uint8), "node": np.zeros(0, np.uint8),
            "src": np.zeros(0, np.uint8), "dst": np.zeros(0, np.uint8),
            "serial": np.zeros(0, np.uint32), "length_samples": np.zeros(0, np.uint32),
            "snr_db": np.zeros(0), "reason": np.zeros(0, np.int8), "retry": np.zeros(0, bool),
            "payload": []}
