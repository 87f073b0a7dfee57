"""The kind of CPU a study row records: the architecture and the vector extensions its
floating-point kernels are chosen by, read from /proc/cpuinfo."""

from __future__ import annotations

import platform

from saggriac.runs.resources import VECTOR_FLAGS, cpu_kind

X86 = """processor\t: 0
model name\t: Some Xeon
flags\t\t: fpu sse sse2 avx fma avx2 avx512f avx512bw avx512_vnni avx512_bf16 avx512_fp16 amx_tile
processor\t: 1
flags\t\t: fpu sse sse2 avx fma avx2 avx512f avx512bw avx512_vnni avx512_bf16 avx512_fp16 amx_tile
"""
ZEN2 = "processor\t: 0\nflags\t\t: fpu sse sse2 avx fma avx2 bmi2\n"
ARM = "processor\t: 0\nFeatures\t: fp asimd evtstrm aes sve\n"


def test_two_cpus_differ_by_their_vector_extensions_and_only_by_those():
    arch = platform.machine()
    assert cpu_kind(X86) == f"{arch} avx avx2 fma avx512f avx512_vnni avx512_bf16 avx512_fp16 amx_tile"
    # Flags no kernel is chosen by (bmi2, avx512bw) do not make two kinds.
    assert cpu_kind(ZEN2) == f"{arch} avx avx2 fma"
    assert cpu_kind(ARM) == f"{arch} asimd sve"
    assert cpu_kind("") == arch


def test_this_machines_kind_is_its_architecture_and_known_extensions():
    words = cpu_kind().split()
    assert words[0] == (platform.machine() or "unknown") and set(words[1:]) <= set(VECTOR_FLAGS)
