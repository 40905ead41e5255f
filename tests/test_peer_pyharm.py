"""benchmarks/peer_pyharm.py (the harmonic-balance peer in `make bench`) without its extra: one line, exit 0,
nothing written, so that make bench goes on where pyHarm (the extra `peers`) is not installed."""

from __future__ import annotations

import importlib.util
import sys

from conftest import ROOT


def test_without_pyharm_the_peer_benchmark_skips_in_one_line(tmp_path, monkeypatch, capsys):
    spec = importlib.util.spec_from_file_location("peer_pyharm", ROOT / "benchmarks" / "peer_pyharm.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setitem(sys.modules, "pyHarm", None)  # import pyHarm raises ImportError
    out = tmp_path / "peer.md"
    monkeypatch.setattr(sys, "argv", ["peer_pyharm.py", "-o", str(out)])
    assert module.main() == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed == ["peer_pyharm: skipped: pyHarm is not installed (pip install -e '.[peers]')"]
    assert not out.exists()
