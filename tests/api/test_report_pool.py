"""The render pool's process: started ahead of the first report when asked to warm up, and
outlived by the pool: one that ends abruptly (killed for memory, or by a signal) fails its
render with one line in the log, and the next render of an ended run gets a new process
instead of the broken executor's refusal."""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
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


def test_warming_up_starts_the_render_process_that_the_first_report_uses(
    tmp_path: Path,
) -> None:
    """The service starts its render process ahead of the first report (once ingest is
    quiet, when a finished run's reports are rendered at once): the process is there before
    any render, with the renderer loaded, and the first report is rendered in it instead of
    waiting for a new one (about 2 s of a 50-million-reading run's first page:
    docs/speed.md)."""
    before = {p.pid for p in multiprocessing.active_children()}
    pool = RenderPool(workers=1, queue=4, share=1.0, retry_after=1, processes=True)
    try:
        pool.warm_up()
        started = [p.pid for p in multiprocessing.active_children() if p.pid not in before]
        assert len(started) == 1
        first = tmp_path / "first"
        pool.render("first", "k", cast(Any, _Writes(first)), in_process=False).result(120)
        assert first.read_text() == str(started[0])
    finally:
        pool.close()


def test_a_pool_of_threads_starts_no_process_to_warm_up() -> None:
    before = {p.pid for p in multiprocessing.active_children()}
    pool = RenderPool(workers=1, queue=4, share=1.0, retry_after=1, processes=False)
    try:
        pool.warm_up()
        assert {p.pid for p in multiprocessing.active_children()} == before
    finally:
        pool.close()


def test_a_render_process_leaves_ctrl_c_to_the_service(tmp_path: Path) -> None:
    """Ctrl-C in a terminal sends SIGINT to the whole process group: the render process
    leaves it to the service, which stops it as it stops, and renders on (it printed a
    KeyboardInterrupt traceback into `make run`'s console before)."""
    before = {p.pid for p in multiprocessing.active_children()}
    pool = RenderPool(workers=1, queue=4, share=1.0, retry_after=1, processes=True)
    try:
        first = tmp_path / "first"
        pool.render("first", "k", cast(Any, _Writes(first)), in_process=False).result(120)
        (pid,) = [p.pid for p in multiprocessing.active_children() if p.pid not in before]
        os.kill(pid, signal.SIGINT)
        after = tmp_path / "after"
        pool.render("after", "k", cast(Any, _Writes(after)), in_process=False).result(60)
        assert after.read_text() == first.read_text() == str(pid)
    finally:
        pool.close()
