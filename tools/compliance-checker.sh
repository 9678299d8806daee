#!/usr/bin/env bash
# Build the FMU Compliance Checker (modelica-tools/FMUComplianceChecker, FMI 1.0/2.0)
# offline, from local sources of the checker and of FMI Library (FMIL).
#
# Usage:
#   tools/compliance-checker.sh CHECKER_SRC FMIL_SRC OUT_DIR
#
#   CHECKER_SRC  checker source tree, or a git directory (bare/mirror) to export from
#   FMIL_SRC     FMI Library source tree, or a git directory (bare/mirror) to export from
#   OUT_DIR      build directory; the executable ends up as OUT_DIR/fmuCheck.<platform>
#
# Environment:
#   CHECKER_REF  revision exported from a checker git directory (default: HEAD)
#   FMIL_REF     revision exported from an FMIL git directory (default: 2.0.3, the
#                version the checker's own CMakeLists.txt pins; 2.1 .. 2.4.1 also build.
#                FMIL 3.x does not: its API dropped the FMI_PLATFORM macro and more)
#   JOBS         parallel build jobs (default: 2)
#
# Needs cmake >= 3.5, a C/C++ compiler and make; no network access.
#
# Patches applied to the checker's CMakeLists.txt (the sources are not changed):
#   1. ExternalProject_Add(fmil ...): the GIT_REPOSITORY/GIT_TAG download of FMIL from
#      GitHub is replaced by DOWNLOAD_COMMAND "" and FMIL is placed in FMUCHK_HOME/FMIL
#      (the SOURCE_DIR the checker already uses), so the build needs no network.
#   2. -DFMILIB_BUILD_TESTS=OFF instead of ON: FMIL's own test programs and test FMUs are
#      not needed to build the checker and are not built. (The checker's ctest
#      targets that use FMIL's test FMUs are therefore not usable; they are not run here.)
#   3. The version strings come from `svn info` (GetVersion.cmake) and would read "Test";
#      they are set to the exported git revisions instead, so `fmuCheck -v` names them.
#   4. -DCMAKE_INSTALL_PREFIX is passed to FMIL too (= the FMILIB_INSTALL_PREFIX the checker
#      already passes): FMIL 3.x reads only CMAKE_INSTALL_PREFIX and would otherwise install
#      into /usr/local. Harmless for FMIL 2.x, which reads FMILIB_INSTALL_PREFIX.
#   5. (not a patch: compiler flags) CFLAGS gets -Wno-error= for implicit function
#      declarations, incompatible pointer types and int conversions: the checker
#      (tolower without <ctype.h>) and FMIL's bundled zlib, minizip and flex output rely on
#      them, which GCC >= 14 and Clang >= 16 reject as errors by default.
set -euo pipefail

if [ $# -ne 3 ]; then
    sed -n '2,17p' "$0" >&2
    exit 2
fi
checker_src=$1
fmil_src=$2
out_dir=$3
checker_ref=${CHECKER_REF:-HEAD}
fmil_ref=${FMIL_REF:-2.0.3}
jobs=${JOBS:-2}

command -v cmake >/dev/null || { echo "cmake not found (Debian: apt-get install cmake)" >&2; exit 1; }

is_git_dir() { [ "$(git -C "$1" rev-parse --is-bare-repository 2>/dev/null)" = true ]; }

# export_tree SRC REF DEST: copy a source tree, or export REF from a git directory.
# Prints a version label for the tree.
export_tree() {
    local src=$1 ref=$2 dest=$3
    rm -rf "$dest"
    mkdir -p "$dest"
    if is_git_dir "$src"; then
        git -C "$src" archive --format=tar "$ref" | tar -x -C "$dest"
        local label
        label=$(git -C "$src" describe --tags --exact-match "$ref" 2>/dev/null ||
            git -C "$src" log -1 --format='git-%h-%cs' "$ref")
        echo "$label"
    elif [ -f "$src/CMakeLists.txt" ]; then
        cp -a "$src/." "$dest/"
        if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
            git -C "$src" describe --tags --always --dirty
        else
            echo "local-source"
        fi
    else
        echo "neither a git directory nor a source tree with CMakeLists.txt: $src" >&2
        exit 1
    fi
}

mkdir -p "$out_dir"
out_dir=$(cd "$out_dir" && pwd)
src_dir=$out_dir/src
build_dir=$out_dir/build

checker_version=$(export_tree "$checker_src" "$checker_ref" "$src_dir")
fmil_version=$(export_tree "$fmil_src" "$fmil_ref" "$src_dir/FMIL")
if [ -d "$src_dir/FMIL/src/Import/src/FMI3" ] || [ -d "$src_dir/FMIL/src/XML/src/FMI3" ]; then
    echo "FMIL $fmil_version is a 3.x version: the checker builds only with FMIL 2.x" >&2
    exit 1
fi
echo "checker: $checker_version   FMIL: $fmil_version"

cmakelists=$src_dir/CMakeLists.txt
grep -q 'GIT_REPOSITORY "https://github.com/modelon-community/fmi-library.git"' "$cmakelists" ||
    { echo "unexpected checker CMakeLists.txt: FMIL download not found" >&2; exit 1; }
# Patch 1: no download.
sed -i \
    -e 's|^\([[:space:]]*\)GIT_REPOSITORY "https://github.com/modelon-community/fmi-library.git"|\1DOWNLOAD_COMMAND ""|' \
    -e '/^[[:space:]]*GIT_TAG /d' \
    "$cmakelists"
# Patch 2: no FMIL tests.
sed -i -e 's|-DFMILIB_BUILD_TESTS:BOOLEAN=ON|-DFMILIB_BUILD_TESTS:BOOLEAN=OFF|' "$cmakelists"
# Patch 3: version strings.
sed -i \
    -e "s|^getVersionSVN(\"\${FMUCHK_HOME}\" FMUCHK_VERSION)|set(FMUCHK_VERSION \"$checker_version\")|" \
    -e "s|^getVersionSVN(\"\${FMUCHK_HOME}/FMIL\" FMIL_VERSION)|set(FMIL_VERSION \"$fmil_version\")|" \
    "$cmakelists"
grep -q 'DOWNLOAD_COMMAND ""' "$cmakelists" || { echo "patch 1 failed" >&2; exit 1; }
grep -q 'FMILIB_BUILD_TESTS:BOOLEAN=OFF' "$cmakelists" || { echo "patch 2 failed" >&2; exit 1; }
grep -q "set(FMUCHK_VERSION" "$cmakelists" || { echo "patch 3 failed" >&2; exit 1; }

# Patch 4: FMIL installs into the build directory whatever variable it reads.
sed -i -e 's|^\([[:space:]]*\)-DFMILIB_INSTALL_PREFIX:PATH=\(.*\)$|&\n\1-DCMAKE_INSTALL_PREFIX:PATH=\2|' "$cmakelists"
grep -q -- '-DCMAKE_INSTALL_PREFIX:PATH=${FMUCHK_BUILD}/FMIL/install' "$cmakelists" ||
    { echo "patch 4 failed" >&2; exit 1; }

# Flag 5: old C accepted by newer compilers too (the top-level CMAKE_C_FLAGS is passed to FMIL).
export CFLAGS="${CFLAGS:-} -Wno-error=implicit-function-declaration -Wno-error=incompatible-pointer-types -Wno-error=int-conversion"

rm -rf "$build_dir" # a fresh cache: CMAKE_C_FLAGS and the FMIL settings are cached
mkdir -p "$build_dir"
cmake -S "$src_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release \
    -DFMUCHK_INSTALL_PREFIX="$out_dir" >"$out_dir/cmake-configure.log" 2>&1 ||
    { tail -30 "$out_dir/cmake-configure.log" >&2; exit 1; }
cmake --build "$build_dir" -j "$jobs" >"$out_dir/cmake-build.log" 2>&1 ||
    { tail -40 "$out_dir/cmake-build.log" >&2; exit 1; }
cmake --install "$build_dir" >>"$out_dir/cmake-build.log" 2>&1

checker=$(ls "$out_dir"/fmuCheck.* | head -n 1)
"$checker" -v
echo "built: $checker"
