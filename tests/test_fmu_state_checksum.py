"""A serialised FMU state carries the CRC-32 of its bytes (snapshot.c), FMI
2.0 and 3.0: every single-bit corruption of it, the checksum's own bits
included, is refused by fmi2DeSerializeFMUstate / fmi3DeserializeFMUState
with one log line and no state; an intact one restores bit for bit and the
run from it is the run from the state it was taken of."""
import ctypes
import zlib

import numpy as np
import pytest

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

import fmu_support as T

FMI_ERROR = 3
#: fmpy's names of the FMU state calls, and the C deserialising call, of each version
CALLS = {2: ("getFMUstate", "setFMUstate", "freeFMUstate", "serializeFMUstate", "deSerializeFMUstate",
             "fmi2DeSerializeFMUstate"),
         3: ("getFMUState", "setFMUState", "freeFMUState", "serializeFMUState", "deserializeFMUState",
             "fmi3DeserializeFMUState")}


class Slave:
    """A co-simulation instance of the paper rig's FMU, its error lines kept."""

    def __init__(self, version, d, md, name):
        self.version = version
        cls = FMU2Slave if version == 2 else FMU3Slave
        self.fmu = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                       instanceName=name)
        self.vr = next(v.valueReference for v in md.modelVariables if v.name == "oil.pressure")
        if version == 2:
            self.rec = T.Recorder(name)
            self.fmu.instantiate(callbacks=self.rec.callbacks)
            self.fmu.setupExperiment(startTime=0.0, stopTime=0.02)
            self.fmu.enterInitializationMode()
        else:
            self.lines = []
            self.fmu.instantiate(logMessage=lambda env, st, cat, msg: self.lines.append((st, msg.decode())))
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=0.02)
        self.fmu.exitInitializationMode()

    def call(self, k: int, *args):
        """The k-th of CALLS (get, set, free, serialize, deserialize) through fmpy."""
        return getattr(self.fmu, CALLS[self.version][k])(*args)

    def errors(self) -> list[str]:
        return self.rec.errors() if self.version == 2 else [m for s, m in self.lines if s >= FMI_ERROR]

    def clear(self):
        self.rec.clear() if self.version == 2 else self.lines.clear()

    def run(self, t0: float, n: int, h: float = 1e-4) -> np.ndarray:
        out = []
        for k in range(n):
            self.fmu.doStep(t0 + k * h, h)
            out.append((self.fmu.getReal if self.version == 2 else self.fmu.getFloat64)([self.vr])[0])
        return np.array(out)

    def raw_deserialize(self, data: bytes) -> tuple[int, int | None]:
        """(status, state pointer) of the C call on ``data``."""
        f = T.untyped(self.fmu.dll, CALLS[self.version][5])
        buf = ctypes.create_string_buffer(data, len(data))
        state = ctypes.c_void_p(None)
        st = f(ctypes.c_void_p(self.fmu.component), buf, ctypes.c_size_t(len(data)), ctypes.byref(state))
        return st, state.value


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def slave(request, tmp_path_factory):
    path = T.built_fmu("paper", request.param)
    d = tmp_path_factory.mktemp(f"checksum{request.param}")
    extract(path, str(d))
    s = Slave(request.param, str(d), read_model_description(path), f"crc{request.param}")
    s.run(0.0, 30)                       # t = 3 ms: in contact, every state moving
    yield s
    s.fmu.freeInstance()


def test_the_checksum_is_the_crc32_of_the_state(slave):
    ser = bytes(slave.call(3, slave.call(0)))
    assert len(ser) > 4 and int.from_bytes(ser[-4:], "little") == zlib.crc32(ser[:-4])


def test_an_intact_state_restores_bit_for_bit(slave):
    """Deserialised and set, the state serialises to the same bytes, and the
    run from it is the run from the state it was taken of (both restart the
    solver there)."""
    s = slave.call(0)
    ser = bytes(slave.call(3, s))
    slave.call(1, s)
    ahead = slave.run(0.003, 20)
    restored = slave.call(4, ser)
    slave.call(1, restored)
    assert bytes(slave.call(3, slave.call(0))) == ser
    assert np.array_equal(slave.run(0.003, 20), ahead)
    slave.call(1, s)
    slave.call(2, s)
    slave.call(2, restored)


def test_every_flipped_bit_is_refused_in_one_line(slave):
    """All len * 8 single-bit corruptions (about 3,500 here): each fmi*Error,
    no state handed out, one error line saying the state is corrupted."""
    ser = bytes(slave.call(3, slave.call(0)))
    fname = CALLS[slave.version][5]
    lines = set()
    for bit in range(8 * len(ser)):
        bad = bytearray(ser)
        bad[bit // 8] ^= 1 << (bit % 8)
        slave.clear()
        st, state = slave.raw_deserialize(bytes(bad))
        errs = slave.errors()
        assert st == FMI_ERROR and state is None and len(errs) == 1, (bit, st, errs)
        lines.add(errs[0].split(" (")[0])
    assert lines == {f"{fname}: the serialized state is corrupted"}, lines
    # the intact bytes still pass
    good = slave.call(4, ser)
    slave.call(2, good)


def test_a_truncated_or_extended_state_is_refused(slave):
    ser = bytes(slave.call(3, slave.call(0)))
    for data in (ser[:-1], ser + b"\0", ser[:-4]):
        slave.clear()
        st, state = slave.raw_deserialize(data)
        errs = slave.errors()
        assert st == FMI_ERROR and state is None and len(errs) == 1, errs
        assert f"{len(data)} bytes, but a serialized state of this FMU has {len(ser)}" in errs[0], errs
