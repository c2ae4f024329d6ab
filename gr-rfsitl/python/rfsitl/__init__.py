"""rfsitl: GNU Radio blocks that make a flowgraph an external node of the
rfsitl RF channel emulator (emulator_source, emulator_sink) and speak the
UB-ANC net-port framing (ubanc_framing). fake_emulator is a stand-in for the
emulator's socket, for tests."""

from .rfsitl_python import emulator_sink, emulator_source, ubanc_framing

__all__ = ["emulator_sink", "emulator_source", "ubanc_framing"]
