#!/usr/bin/env bash
# The one test command of hydrofmu: installs what it needs, then runs every check.
#   bash tests/run.sh
# Exits non-zero on any failure. Works on a fresh machine (Debian, Rust toolchain, CPython 3.11).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

step() { printf '\n==> %s\n' "$*"; }

step "Debian packages"
missing=()
python3 -c 'import venv, ensurepip' 2>/dev/null || missing+=(python3-venv)
command -v unzip >/dev/null || missing+=(unzip)
if ((${#missing[@]})); then
  if [[ $(id -u) -eq 0 ]]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
  else
    sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
  fi
fi

step "Windows DLL, built in the background (tools/build-windows.sh; log: target/build-windows.log)"
mkdir -p target
bash tools/build-windows.sh >target/build-windows.log 2>&1 &
windows_build=$!

step "Python virtual environment (.venv)"
if [[ ! -x .venv/bin/python ]]; then
  python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/python/requirements.txt

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings

step "cargo doc"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

step "cargo test"
# The fuzz targets run on their own below, with their counts shown.
cargo test --workspace -- --skip fuzz_ --skip model::snapshot::fuzz
step "fuzz targets (executed and accepted cases of each, with their asserted minimums)"
cargo test -p hydrofmu --test fuzz -- --nocapture
cargo test -p hydrofmu --lib model::snapshot::fuzz -- --nocapture

step "release build of the FMU binary and fmu-pack"
cargo build --release --workspace

step "report generators, quick mode: their numbers against docs/VALIDATION.md, docs/PERFORMANCE.md, docs/DRIFT.md and docs/VISCOUS.md"
cargo run --release -q -p fmu-pack --example validation -- --quick --out target/reports
cargo run --release -q -p fmu-pack --example performance -- --quick --out target/reports
cargo run --release -q -p fmu-pack --example drift -- --quick --out target/reports
cargo run --release -q -p fmu-pack --example viscous -- --quick --out target/reports

step "Windows DLL: the FMI 2.0 and 3.0 functions under wine64 against the Linux library (docs/WINDOWS.md)"
if ! wait "$windows_build"; then
  cat target/build-windows.log
  echo "the Windows build failed (log above)" >&2
  exit 1
fi
tail -n 4 target/build-windows.log
# Built from this checkout, in parallel with the Linux library, which may have finished later:
# the DLL is as current as the library (pack's staleness warning compares their times).
touch -c "${CARGO_TARGET_DIR:-target}/release/hydrofmu.dll"
bash tests/windows/run.sh

step "pytest (real FMU archives, built from the current source; they carry the Windows DLL too)"
HYDROFMU_ROOT="$root" .venv/bin/python -m pytest -q tests/python
