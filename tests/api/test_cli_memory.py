"""``rigserver serve`` keeps freed memory for the next request bodies (glibc's malloc)."""

from __future__ import annotations

import platform
import subprocess
import sys

import pytest

# In a process of its own: the tuning is for the life of a process. It prints the bytes
# glibc maps afresh (mallinfo2's hblkhd) for one 8 MB allocation, the size of a batch body.
_PROBE = """
import ctypes, sys
from rigserver.cli import keep_freed_memory

class MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in (
        "arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks",
        "uordblks", "fordblks", "keepcost")]

libc = ctypes.CDLL("libc.so.6")
libc.mallinfo2.restype = MallInfo2
if sys.argv[1] == "tuned":
    assert keep_freed_memory()
before = libc.mallinfo2().hblkhd
body = bytearray(8 << 20)
print(libc.mallinfo2().hblkhd - before)
"""


def _mapped_afresh(mode: str) -> int:
    out = subprocess.run(
        [sys.executable, "-c", _PROBE, mode], capture_output=True, text=True, check=True
    )
    return int(out.stdout)


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the tuning is glibc's")
def test_a_batch_body_comes_from_the_heap_once_tuned() -> None:
    # glibc's default maps anything over 128 KiB afresh (and unmaps it when freed)
    assert _mapped_afresh("default") >= 8 << 20
    assert _mapped_afresh("tuned") == 0
