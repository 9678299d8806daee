"""Shared fixtures: FMU archives packed from the current source by the release fmu-pack.

`bash tests/run.sh` builds the release binaries first; if they are missing the fixture builds
them (cargo build --release). Archives go to a session temporary directory.
"""
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(os.environ.get("HYDROFMU_ROOT", pathlib.Path(__file__).resolve().parents[2]))
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
if not TARGET.is_absolute():
    TARGET = ROOT / TARGET
NETWORKS = ROOT / "examples" / "networks"

# name -> (network file, extra pack arguments)
FMUS = {
    "Seed": ("seed_2dof.xml", []),
    "SeedKeep": ("seed_2dof.xml", ["--keep-inf-mass"]),
    "TwoDof": ("two-dof-sway-heave.xml", []),
}


def _release_binaries():
    fmu_pack = TARGET / "release" / "fmu-pack"
    library = TARGET / "release" / "libhydrofmu.so"
    if not (fmu_pack.is_file() and library.is_file()):
        subprocess.run(
            ["cargo", "build", "--release", "-p", "hydrofmu", "-p", "fmu-pack"],
            cwd=ROOT,
            check=True,
        )
    return fmu_pack, library


@pytest.fixture(scope="session")
def fmus(tmp_path_factory):
    """Paths of the packed archives, by name."""
    fmu_pack, library = _release_binaries()
    out = tmp_path_factory.mktemp("fmus")
    paths = {}
    for name, (network, extra) in FMUS.items():
        path = out / f"{name}.fmu"
        subprocess.run(
            [
                str(fmu_pack),
                "pack",
                "semicircle",
                "--network",
                str(NETWORKS / network),
                "--binary",
                str(library),
                "-o",
                str(path),
                *extra,
            ],
            check=True,
            capture_output=True,
        )
        paths[name] = path
    return paths


@pytest.fixture(scope="session")
def fmu_pack_binary():
    return _release_binaries()[0]
