"""OpenBLAS's kernels for this CPU, chosen before OpenBLAS loads.

OpenBLAS picks its kernels once, when it loads, from the CPU's model number; on a CPU it does not
recognise (a virtual machine's generic "Intel Xeon Processor") it falls back to SSE kernels that
run dgemm several times slower than the CPU's AVX-512 or AVX2 would. The tailor executable
re-executes itself with OPENBLAS_CORETYPE set in that case (forward/solve/blas_info.hpp); a
Python process cannot, so importing tailor sets OPENBLAS_CORETYPE from the CPU's flags when no
BLAS is loaded yet (import tailor before NumPy, or set OPENBLAS_CORETYPE yourself).
docs/performance.md, "BLAS kernels".
"""
from __future__ import annotations

import os

_AVX512 = {"avx512f", "avx512cd", "avx512bw", "avx512dq", "avx512vl"}


def cpu_core(flags: set[str]) -> str | None:
    """The OpenBLAS core for a CPU with these /proc/cpuinfo flags, as bin/tailor chooses it."""
    if _AVX512 <= flags:
        return "SkylakeX"
    if {"avx2", "fma"} <= flags:
        return "Haswell"
    return None


def _cpu_flags() -> set[str]:
    try:
        with open("/proc/cpuinfo", encoding="ascii", errors="replace") as info:
            for line in info:
                if line.startswith("flags"):
                    return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def _blas_loaded() -> bool:
    try:
        with open("/proc/self/maps", encoding="ascii", errors="replace") as maps:
            return any("libblas" in line or "openblas" in line for line in maps)
    except OSError:
        return True  # cannot tell: leave the choice to OpenBLAS


def choose() -> None:
    """Sets OPENBLAS_CORETYPE for this process and its children, unless it is set or a BLAS is loaded."""
    if "OPENBLAS_CORETYPE" in os.environ or _blas_loaded():
        return
    core = cpu_core(_cpu_flags())
    if core:
        os.environ["OPENBLAS_CORETYPE"] = core
