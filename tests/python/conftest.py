"""Shared fixtures: FMU archives packed from the current source by the release fmu-pack.

`bash tests/run.sh` builds the release binaries first; if they are missing the fixture builds
them (cargo build --release). Archives go to a session temporary directory.
"""
import importlib.util
import os
import pathlib
import subprocess
import zipfile

import pytest

ROOT = pathlib.Path(os.environ.get("HYDROFMU_ROOT", pathlib.Path(__file__).resolve().parents[2]))
TARGET = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
if not TARGET.is_absolute():
    TARGET = ROOT / TARGET
NETWORKS = ROOT / "examples" / "networks"


def load_script(relative_path):
    """A Python file of the repository (e.g. "examples/ships/compare_capytaine.py") as a
    module, for tests that run an example's functions."""
    path = ROOT / relative_path
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module

# name -> (network file, extra pack arguments)
FMUS = {
    "Seed": ("seed_2dof.xml", []),
    "SeedKeep": ("seed_2dof.xml", ["--keep-inf-mass"]),
    "TwoDof": ("two-dof-sway-heave.xml", []),
}

# FMUs computed by the whole pipeline (sweep, fit, pack) for the hard-case suite
# (test_stability.py): name -> how to build it.
#   ("pack", args)            fmu-pack pack ARGS (sweep and fit inside pack)
#   ("repack", name, args)    the network of the pipeline FMU `name`, packed with ARGS
PIPELINE_FMUS = {
    "SemicircleHeave": ("pack", ["semicircle", "--dofs", "heave"]),
    "SemicircleHeaveKeep": (
        "repack", "SemicircleHeave", ["semicircle", "--dofs", "heave", "--keep-inf-mass"]
    ),
    "CircleH11Heave": ("pack", ["circle", "--depth", "1.1", "--dofs", "heave"]),
    "SemicircleHeaveKr20": (
        "pack",
        ["semicircle", "--dofs", "heave", "--kr", "0.01:20:121", "--band", "0.05:20"],
    ),
    "SemicircleHeave2048": (
        "pack",
        ["semicircle", "--dofs", "heave", "--panels", "2048", "--kr", "0.05:5:8"],
    ),
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


@pytest.fixture(scope="session")
def pipeline_fmu(tmp_path_factory):
    """build(name) -> (archive path, everything fmu-pack printed), for the FMUs of
    PIPELINE_FMUS; each is built once per session, when a test first asks for it."""
    fmu_pack, library = _release_binaries()
    out = tmp_path_factory.mktemp("pipeline")
    built = {}

    def run(*args):
        r = subprocess.run([str(fmu_pack), *args], check=True, capture_output=True, text=True)
        return r.stdout + r.stderr

    def build(name):
        if name in built:
            return built[name]
        kind, *spec = PIPELINE_FMUS[name]
        path = out / f"{name}.fmu"
        pack = ["pack", "--binary", str(library), "-o", str(path)]
        if kind == "pack":
            log = run(*pack, *spec[0])
        else:
            source, args = spec
            with zipfile.ZipFile(build(source)[0]) as archive:
                network = out / f"{name}.xml"
                network.write_bytes(archive.read("resources/network.xml"))
            log = run(*pack, *args, "--network", str(network))
        built[name] = (path, log)
        return built[name]

    return build
