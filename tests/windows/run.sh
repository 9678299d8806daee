#!/usr/bin/env bash
# The Windows DLL against the Linux library, through the FMI 2.0 and FMI 3.0 functions
# (docs/WINDOWS.md): packs the WAMIT sphere with both binaries, unpacks each archive into a
# folder whose name has a space and non-ASCII letters, runs tests/windows/fmi_check.c natively
# (dlopen) and under wine64 (LoadLibraryW; Windows paths Z:\..., a file:///Z:/... URI), and
# compares: every output of the 1000 steps to 1e-12 relative, the serialized state byte for
# byte, the state round trip in each.
#
#   bash tools/build-windows.sh && bash tests/windows/run.sh
#
# Needs the Linux library and fmu-pack (cargo build --release --workspace) and the DLL next to
# the Linux library; installs gcc-mingw-w64-x86-64 and wine64 when missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
target_dir=$(realpath "${CARGO_TARGET_DIR:-target}")
release=$target_dir/release
work=$target_dir/windows-test
wine=/usr/lib/wine/wine64
TOLERANCE=1e-12

say() { printf 'windows test: %s\n' "$*" >&2; }
die() { say "FAILED: $*"; exit 1; }

missing=()
command -v x86_64-w64-mingw32-gcc >/dev/null || missing+=(gcc-mingw-w64-x86-64)
[[ -x $wine ]] || missing+=(wine64)
if ((${#missing[@]})); then
  sudo=()
  [[ $(id -u) -eq 0 ]] || sudo=(sudo)
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
for f in "$release/libhydrofmu.so" "$release/fmu-pack" "$release/hydrofmu.dll"; do
  [[ -f $f ]] || die "$f missing (cargo build --release --workspace; bash tools/build-windows.sh)"
done

rm -rf "$work" && mkdir -p "$work/bin"
gcc -std=c11 -O2 -Wall -Wextra -Werror -o "$work/bin/fmi_check" tests/windows/fmi_check.c -ldl -lm
x86_64-w64-mingw32-gcc -std=c11 -O2 -Wall -Wextra -Werror -s -o "$work/bin/fmi_check.exe" tests/windows/fmi_check.c
# Test-only: Wine 8.0 lacks bcryptprimitives.dll; the program's folder is searched first.
x86_64-w64-mingw32-gcc -O2 -Wall -Werror -s -shared -o "$work/bin/bcryptprimitives.dll" \
  tests/windows/bcryptprimitives.c -lbcrypt

export WINEPREFIX=$work/wine-prefix WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
start=$SECONDS
"$wine" wineboot --init >/dev/null 2>&1 || die "wineboot"
say "wine prefix: $((SECONDS - start)) s"

# Windows spelling of a Linux path (Wine maps / to Z:).
windows_path() { printf 'Z:%s' "${1//\//\\}"; }
# A file: URI of an absolute path: every byte but [A-Za-z0-9/._~-] percent-encoded.
file_uri() {
  local path=$1 out="" i c
  local LC_ALL=C
  for ((i = 0; i < ${#path}; i++)); do
    c=${path:i:1}
    case $c in
      [A-Za-z0-9/._~-]) out+=$c ;;
      *) out+=$(printf '%%%02X' "'$c") ;;
    esac
  done
  printf 'file://%s' "$out"
}
# Value references: the velocity inputs, then the outputs (force*, power, energy).
references() {
  python3 - "$1" <<'PY'
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
variables = [(v.get("name"), v.get("valueReference"))
             for v in root.find("ModelVariables") if v.get("valueReference")]
print(" ".join(r for n, r in variables if n.startswith("velocity.")))
print(" ".join(r for n, r in variables if n.startswith("force") or n in ("power", "energy")))
PY
}

for fmi in 2 3; do
  archive=$work/Sphere$fmi.fmu
  "$release/fmu-pack" pack tests/data/wamit/sphere.1 --fmi "$fmi" -o "$archive" >"$work/pack$fmi.txt"
  grep -q "platforms        $([[ $fmi == 2 ]] && echo 'linux64, win64' || echo 'x86_64-linux, x86_64-windows')\$" \
    "$work/pack$fmi.txt" || die "the summary does not list both platforms: $(cat "$work/pack$fmi.txt")"
  dir="$work/unpacked $fmi dé海"
  mkdir -p "$dir" && (cd "$dir" && unzip -q "$archive")
  id=Sphere$fmi
  read -r guid < <(grep -oE '(guid|instantiationToken)="[^"]*"' "$dir/modelDescription.xml" | cut -d'"' -f2)
  { read -r velocities; read -r outputs; } < <(references "$dir/modelDescription.xml")
  # Calm water by default. HYDROFMU_CHECK_PARAMETERS="i:2=1 3=2 4=8 5=0" (regular waves, 2 m,
  # 8 s, heading 0) adds the exciting force; with it the state round trip does not hold today
  # (docs/WINDOWS.md).
  parameters=${HYDROFMU_CHECK_PARAMETERS-}
  if [[ $fmi == 2 ]]; then
    linux_lib=$dir/binaries/linux64/$id.so
    windows_lib=$(windows_path "$dir/binaries/win64/$id.dll")
    linux_resources=$(file_uri "$dir/resources")
    windows_resources=$(file_uri "/$(windows_path "$dir/resources" | tr '\\' /)")
  else
    linux_lib=$dir/binaries/x86_64-linux/$id.so
    windows_lib=$(windows_path "$dir/binaries/x86_64-windows/$id.dll")
    linux_resources="$dir/resources/"
    windows_resources="$(windows_path "$dir/resources")\\"
  fi
  printf '%s\n' "$fmi" "$linux_lib" "$linux_resources" "$guid" "$velocities" "$outputs" "$parameters" >"$work/linux$fmi.cfg"
  printf '%s\n' "$fmi" "$windows_lib" "$windows_resources" "$guid" "$velocities" "$outputs" "$parameters" >"$work/windows$fmi.cfg"
  "$work/bin/fmi_check" "$work/linux$fmi.cfg" "$work/linux$fmi.out" || die "FMI $fmi on Linux"
  start=$SECONDS
  "$wine" "$work/bin/fmi_check.exe" "$(windows_path "$work/windows$fmi.cfg")" \
    "$(windows_path "$work/windows$fmi.out")" || die "FMI $fmi under wine64"
  say "FMI $fmi under wine64: $((SECONDS - start)) s (resources: $windows_resources)"
  # The outputs, value by value, to TOLERANCE relative; the state lines byte for byte.
  awk -v tol="$TOLERANCE" -v fmi="$fmi" '
    function abs(x) { return x < 0 ? -x : x }
    NR == FNR { linux[FNR] = $0; n = FNR; next }
    {
      if (!(FNR in linux)) { print "extra line " FNR; bad = 1; exit }
      if ($1 == "state" || $1 == "restored") {
        if ($0 != linux[FNR]) { print "line " FNR " (" $1 ") differs"; bad = 1 }
        if ($1 == "restored") restored++
        next
      }
      split(linux[FNR], l, " ")
      for (i = 1; i <= NF; i++) {
        a = l[i] + 0; b = $i + 0; scale = abs(a) > abs(b) ? abs(a) : abs(b)
        d = abs(a - b); if (d > worst_abs) worst_abs = d
        if (scale > 0 && d / scale > worst) worst = d / scale
        if (d > tol * scale) { print "step " FNR " column " i ": " l[i] " against " $i; bad = 1 }
        values++
      }
    }
    END {
      if (FNR != n) { print "line counts differ"; bad = 1 }
      if (restored != 1) { print "no state round trip"; bad = 1 }
      printf "FMI %s: %d values, largest relative difference %.3g, state identical\n", fmi, values, worst
      exit bad
    }' "$work/linux$fmi.out" "$work/windows$fmi.out" || die "FMI $fmi: the DLL differs from the Linux library"
done
say "passed"
