"""Smoke test of the Python side: the pinned co-simulation masters import and start."""
import importlib.metadata


def test_fmpy_is_the_pinned_version():
    import fmpy

    assert fmpy.__version__ == "0.3.32"


def test_libcosimpy_imports_and_creates_an_execution():
    assert importlib.metadata.version("libcosimpy") == "0.0.6"
    from libcosimpy.CosimExecution import CosimExecution

    execution = CosimExecution.from_step_size(step_size=int(1e7))  # 10 ms in ns
    assert execution is not None
    assert execution.status().current_time == 0
