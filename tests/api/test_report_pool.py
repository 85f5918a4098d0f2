"""The render pool outlives its render process: one that ends abruptly (killed for memory,
or by a signal) fails its render with one line in the log, and the next render of an ended
run gets a new process instead of the broken executor's refusal."""

from __future__ import annotations

import logging
import os
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any, cast

import pytest

from rigserver.api.report_pool import RenderPool


class _Dies:
    """A job whose process ends at once, as one killed by the kernel would."""

    def render(self) -> None:
        os._exit(9)


class _Writes:
    """A job that writes its file (proof that a process took it)."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def render(self) -> None:
        self.path.write_text(str(os.getpid()))


def test_a_render_process_that_ends_abruptly_is_replaced(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    pool = RenderPool(workers=1, queue=4, share=1.0, retry_after=1, processes=True)
    try:
        first = tmp_path / "first"
        pool.render("first", "k", cast(Any, _Writes(first)), in_process=False).result(60)
        with caplog.at_level(logging.WARNING, logger="rigserver"):
            dying = pool.render("dies", "k", cast(Any, _Dies()), in_process=False)
            with pytest.raises(BrokenProcessPool):
                dying.result(60)
        assert [r.getMessage() for r in caplog.records] == [
            "rendering dies stopped: its render process ended abruptly"
        ]
        after = tmp_path / "after"
        pool.render("after", "k", cast(Any, _Writes(after)), in_process=False).result(60)
        assert after.read_text() != first.read_text()  # another process
        assert pool.admitted.renders == 0
    finally:
        pool.close()
