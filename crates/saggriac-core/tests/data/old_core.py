"""What the test-data writers share: the core of an older commit loaded from its built file, and
a float as the bits the tests compare."""
import importlib.util
import struct


def load(path):
    """The extension module built at that commit (its _core .so), loaded from ``path``."""
    spec = importlib.util.spec_from_file_location("_core", path)
    core = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(core)
    return core


def bits(v):
    return struct.unpack("<Q", struct.pack("<d", float(v)))[0]
