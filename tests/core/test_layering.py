"""The model library must stay free of the web, pydantic and HDF5 (style.md, habit 1)."""

import subprocess
import sys


def test_importing_core_loads_no_web_no_hdf5_no_pydantic() -> None:
    code = (
        "import sys, importlib, pkgutil, rigserver.core as c\n"
        "for m in pkgutil.iter_modules(c.__path__):\n"
        "    importlib.import_module('rigserver.core.' + m.name)\n"
        "bad = sorted(n for n in ('fastapi', 'h5py', 'pydantic', 'starlette', 'httpx')"
        " if n in sys.modules)\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.strip()
    assert out == ""
