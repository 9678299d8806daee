#!/usr/bin/env bash
# Builds the hydrofmu FMU library for Windows x86_64 (hydrofmu.dll) on Debian, from Debian
# packages only, and puts it next to the Linux library, where `fmu-pack pack` finds it
# (docs/WINDOWS.md).
#
#   bash tools/build-windows.sh            # installs what is missing, builds, checks
#   bash tools/build-windows.sh --check    # only reports the toolchain against the pins
#
# Environment: CARGO_TARGET_DIR (default target/): the DLL goes to $CARGO_TARGET_DIR/release/;
# HYDROFMU_WINDOWS_TARGET_DIR (default $CARGO_TARGET_DIR/windows-build): cargo's build folder
# for the Windows target (std and the dependencies are built there once, ~0.5 GB);
# HYDROFMU_WINDOWS_STRICT=1: a toolchain that differs from the pins below is an error.
#
# The toolchain: Debian's rustc-web/cargo-web (Rust with the standard library's sources,
# rust-web-src), which builds std for x86_64-pc-windows-gnu itself (-Zbuild-std; no rustup
# target needed), and the MinGW-w64 cross compiler as the linker. Exits non-zero, saying why,
# on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."

# The versions this build was checked with (tests/windows/run.sh: the DLL's forces against the
# Linux library's). Debian keeps only the newest of each in its archive, so a change is
# reported, not prevented.
PINNED=(
  "rustc-web 1.96.0+dfsg1-1~deb12u2"
  "cargo-web 1.96.0+dfsg1-1~deb12u2"
  "rust-web-src 1.96.0+dfsg1-1~deb12u2"
  "gcc-mingw-w64-x86-64 12.2.0-14+25.2"
)
TRIPLE=x86_64-pc-windows-gnu
RUSTC=/usr/bin/rustc   # Debian's, not rustup's (first on PATH, without the std sources)
CARGO=/usr/bin/cargo
LINKER=x86_64-w64-mingw32-gcc
MAX_DLL_BYTES=$((3 * 1024 * 1024))

say() { printf 'build-windows: %s\n' "$*" >&2; }
die() { say "FAILED: $*"; exit 1; }

installed_version() { dpkg-query -W -f='${Status} ${Version}\n' "$1" 2>/dev/null | awk '/install ok installed/ {print $4}'; }

check_pins() {
  local changed=0 line name pinned now
  for line in "${PINNED[@]}"; do
    read -r name pinned <<<"$line"
    now=$(installed_version "$name")
    if [[ -z $now ]]; then
      say "$name is not installed"; changed=1
    elif [[ $now != "$pinned" ]]; then
      say "TOOLCHAIN CHANGED: $name is $now, the build was checked with $pinned:"
      say "  run tests/windows/run.sh, then update PINNED in tools/build-windows.sh"
      changed=1
    fi
  done
  return $changed
}

if [[ ${1:-} == --check ]]; then
  check_pins && say "toolchain as pinned"
  exit
fi
[[ $# -eq 0 ]] || die "unknown argument '$1' (usage: tools/build-windows.sh [--check])"

# 1. Packages.
start=$SECONDS
missing=()
for line in "${PINNED[@]}"; do
  read -r name _ <<<"$line"
  [[ -n $(installed_version "$name") ]] || missing+=("$name")
done
if ((${#missing[@]})); then
  say "installing ${missing[*]} (apt-get)"
  sudo=()
  [[ $(id -u) -eq 0 ]] || sudo=(sudo)
  "${sudo[@]}" apt-get update -qq || die "apt-get update"
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null || die "apt-get install ${missing[*]}"
fi
say "packages: $((SECONDS - start)) s"
if ! check_pins; then
  [[ ${HYDROFMU_WINDOWS_STRICT:-0} == 1 ]] && die "toolchain differs from the pins (HYDROFMU_WINDOWS_STRICT=1)"
fi
for tool in "$RUSTC" "$CARGO" "$LINKER"; do
  command -v "$tool" >/dev/null || die "$tool not found after installing the packages"
done
say "$("$RUSTC" --version), $("$LINKER" --version | head -n1)"

# 2. The DLL. Size (docs/WINDOWS.md): fat LTO drops the code no exported function reaches
# (the linker's section collection keeps most of it on Windows) and the symbol table is
# stripped; the Linux build's profile is left as it is.
target_dir=${CARGO_TARGET_DIR:-target}
windows_dir=${HYDROFMU_WINDOWS_TARGET_DIR:-$target_dir/windows-build}
start=$SECONDS
RUSTC=$RUSTC RUSTC_BOOTSTRAP=1 \
  CARGO_TARGET_DIR="$windows_dir" \
  CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=$LINKER \
  CARGO_PROFILE_RELEASE_LTO=fat \
  CARGO_PROFILE_RELEASE_STRIP=symbols \
  "$CARGO" rustc --release -p hydrofmu --lib --crate-type cdylib --target "$TRIPLE" \
  -Zbuild-std=std,panic_abort ||
  die "cargo build for $TRIPLE (see above)"
say "build: $((SECONDS - start)) s"

# 3. Checks: a PE DLL, its fmi2/fmi3 functions exported, only Windows system DLLs imported.
dll=$windows_dir/$TRIPLE/release/hydrofmu.dll
[[ -f $dll ]] || die "$dll was not built"
[[ $(head -c2 "$dll") == MZ ]] || die "$dll is not a PE file"
dump=$(x86_64-w64-mingw32-objdump -p "$dll")
exports=$(grep -cE '^\s+\[ *[0-9]+\] fmi[23]' <<<"$dump" || true)
[[ $exports -gt 100 ]] || die "$dll exports $exports fmi2/fmi3 functions (expected over 100)"
imports=$(awk '/DLL Name:/ {print $3}' <<<"$dump" | sort -u | tr '\n' ' ')
for import in $imports; do
  case ${import,,} in
    kernel32.dll | ntdll.dll | msvcrt.dll | bcryptprimitives.dll | ws2_32.dll | \
      userenv.dll | advapi32.dll | api-ms-win-*) ;;
    *) die "$dll imports $import (only Windows system DLLs are allowed)" ;;
  esac
done
bytes=$(stat -c %s "$dll")
((bytes <= MAX_DLL_BYTES)) || die "$dll is $bytes bytes, over the limit of $MAX_DLL_BYTES"
mkdir -p "$target_dir/release"
cp "$dll" "$target_dir/release/hydrofmu.dll"
say "$exports fmi2/fmi3 functions exported; imports: $imports"
say "$bytes bytes"
echo "$target_dir/release/hydrofmu.dll"
