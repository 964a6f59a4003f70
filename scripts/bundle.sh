#!/usr/bin/env bash
# Makes a relocatable hdrconform bundle: one folder that runs the suite on another x86-64 Linux
# machine with only glibc and a Vulkan driver installed (README.md, "Running on a GPU machine
# (bundle)").
#
#   scripts/bundle.sh --out DIR [--build BUILD_DIR] [--no-build] [--no-stubs]
#
# DIR/hdrconform                  the launcher (POSIX sh): sets the library path, runs bin/
# DIR/bin/hdrconform              the binary, debug info stripped (objcopy --strip-debug)
# DIR/lib/                        every library it needs but glibc's, under its SONAME; the
#                                 Vulkan loader libvulkan.so.1 included
# DIR/lib/compat/                 libstdc++.so.6 and libgcc_s.so.1: used only where the host's
#                                 are missing or older than the build's (the launcher checks)
# DIR/gpu-check                   scripts/gpu-check.py: the suite, its planted defects and
#                                 (optionally) gpu_tests on a real GPU, summarised (Python 3)
# DIR/share/hdrconform/           cases/, goldens/, shaders/ (gpu/shaders), source_commit,
#                                 planted_shader_defects.json: the
#                                 binary finds them from its own path (core/install_paths.h)
# DIR/MANIFEST.txt                every library, where it came from, and which ones are stubs
#
# OpenImageIO (Debian 12: 2.4, plugins built in) links about 20 format and colour libraries whose
# closure is 257 libraries, 362 MB (openvdb, ffmpeg with its codecs, opencv, dcmtk, libraw,
# OpenColorIO, heif, ...). hdrconform reads and writes only OpenEXR and PNG, so each OpenImageIO
# dependency not in keep_prefixes below is replaced by a stub: a shared object with the same SONAME
# that defines every symbol the bundled objects import from it (OpenImageIO is linked with
# BIND_NOW, so all must resolve at load), each object zeroed memory of the real one's size, each
# function printing its name and aborting if called, but those a normal run calls (found by
# running the bundle in trace mode, below), which return zeroed memory. The stubs' own
# dependencies are not bundled. --no-stubs bundles the real libraries instead (422 MB). Built with
# the system C compiler. docs/bundle.md.
#
# Before it finishes the script checks that every library but glibc's resolves inside the bundle
# and that the bundle starts and lists its cases. The test runner/bundle_test.sh runs cases of
# every pipeline from a copy with the source and build trees hidden.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
out="" build="${HDRC_BUILD_DIR:-$root/build}" do_build=1 stubs=1
usage() { sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="${2:?--out needs a folder}"; shift 2 ;;
    --build) build="${2:?--build needs a folder}"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --no-stubs) stubs=0; shift ;;
    -h | --help) usage ;;
    *) echo "bundle: unknown argument: $1" >&2; usage ;;
  esac
done
[ -n "$out" ] || usage
for tool in objcopy readelf nm cc ldd; do
  command -v "$tool" >/dev/null || { echo "bundle: $tool is needed (binutils, gcc)" >&2; exit 1; }
done

if [ "$do_build" = 1 ]; then HDRC_BUILD_DIR="$build" "$root/scripts/build.sh"; fi
binary="$build/runner/hdrconform"
[ -x "$binary" ] || { echo "bundle: no $binary (run scripts/build.sh)" >&2; exit 1; }

# A folder is replaced only when it is empty or an earlier bundle.
if [ -e "$out" ]; then
  if [ -f "$out/MANIFEST.txt" ] && [ -x "$out/bin/hdrconform" ]; then
    rm -rf "$out"
  elif [ -n "$(ls -A "$out")" ]; then
    echo "bundle: $out exists and is not an earlier bundle; choose an empty or new folder" >&2
    exit 1
  fi
fi
mkdir -p "$out/bin" "$out/lib/compat" "$out/share/hdrconform"
out="$(cd "$out" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# glibc's own libraries: always the host's (a program cannot bring its own libc without its own
# dynamic linker). libstdc++ and libgcc_s go to lib/compat (the launcher's check).
glibc=" libc.so.6 libm.so.6 libmvec.so.1 libpthread.so.0 libdl.so.2 librt.so.1 libresolv.so.2 "
glibc+=" libutil.so.1 libanl.so.1 ld-linux-x86-64.so.2 "  # " NAME " matches one
compat=" libstdc++.so.6 libgcc_s.so.1 "
# What OpenImageIO needs for OpenEXR and PNG (and itself); its other dependencies are stubbed.
keep_prefixes="libOpenImageIO_Util. libz. libpng libOpenEXR libOpenEXRCore libImath libIex
  libIlmThread libtbb libboost_thread"

# SONAME -> path as the dynamic linker resolves them here (ldd: the whole closure).
declare -A path_of
while read -r name _ path _; do
  [ -n "$path" ] && [ -f "$path" ] && path_of[$name]="$path"
done < <(ldd "$binary" | awk '$2 == "=>" {print $1, $2, $3}')
needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'; }

oiio=""
for n in $(needed "$binary"); do case "$n" in libOpenImageIO.so.*) oiio="$n" ;; esac; done
declare -A stub=()
if [ "$stubs" = 1 ] && [ -n "$oiio" ]; then
  for n in $(needed "${path_of[$oiio]}"); do
    case "$glibc$compat" in *" $n "*) continue ;; esac
    kept=0
    for p in $keep_prefixes; do case "$n" in "$p"*) kept=1 ;; esac; done
    [ "$kept" = 1 ] || stub[$n]=1
  done
fi

# The real libraries: the NEEDED closure of the binary, not entering glibc or the stubs.
declare -A real=()
queue=($(needed "$binary"))
while [ ${#queue[@]} -gt 0 ]; do
  n="${queue[0]}"
  queue=("${queue[@]:1}")
  case "$glibc" in *" $n "*) continue ;; esac
  [ -n "${stub[$n]:-}" ] || [ -n "${real[$n]:-}" ] && continue
  [ -n "${path_of[$n]:-}" ] || { echo "bundle: ldd does not resolve $n" >&2; exit 1; }
  real[$n]="${path_of[$n]}"
  queue+=($(needed "${path_of[$n]}"))
done

objcopy --strip-debug "$binary" "$out/bin/hdrconform"
manifest="$out/MANIFEST.txt"
{
  echo "hdrconform bundle made by scripts/bundle.sh from commit $(git -C "$root" rev-parse HEAD 2>/dev/null || echo unknown)"
  echo "on $(uname -m) $(. /etc/os-release 2>/dev/null && echo "$PRETTY_NAME"); glibc $(ldd --version | sed -n '1s/.* //p')"
  echo
  echo "real libraries (lib/, lib/compat/), from:"
} >"$manifest"
for n in $(printf '%s\n' "${!real[@]}" | sort); do
  dest="$out/lib/$n"
  case "$compat" in *" $n "*) dest="$out/lib/compat/$n" ;; esac
  cp -L "${real[$n]}" "$dest"
  echo "  $n  ${real[$n]}" >>"$manifest"
done

# Stubs. Symbols imported by the binary and the bundled libraries, and those defined by what is
# bundled or on every host (a stub must not capture a weak C++ template instance that a real
# library also defines: only unversioned imports are checked, a versioned one names its library).
if [ ${#stub[@]} -gt 0 ]; then
  consumers=("$binary")
  for n in "${!real[@]}"; do consumers+=("${real[$n]}"); done
  for o in "${consumers[@]}"; do nm -D --undefined-only --with-symbol-versions "$o"; done |
    awk '{print $NF}' | sort -u >"$work/imports"
  others=("${consumers[@]}")
  for n in $glibc $compat; do [ -n "${path_of[$n]:-}" ] && others+=("${path_of[$n]}"); done
  for o in "${others[@]}"; do nm -D --defined-only "$o"; done |
    awk 'NF >= 3 {sub(/@.*/, "", $3); print $3}' | sort -u >"$work/defined"
fi
# make_stubs BENIGN: writes every stub into lib/. A function listed in BENIGN ("SONAME SYMBOL"
# lines) returns zeroed memory (as a string: ""); any other prints its name and aborts, or, where
# HDRC_STUB_TRACE names a file, appends "SONAME SYMBOL" to it and returns zeroed memory.
make_stubs() {
  local benign="$1" n src c map nfunc ndata
  : >"$work/stubs.txt"
  for n in $(printf '%s\n' "${!stub[@]}" | sort); do
    src="${path_of[$n]:-}"
    [ -n "$src" ] || { echo "bundle: ldd does not resolve $n" >&2; exit 1; }
    c="$work/$n.c" map="$work/$n.map"
    rm -f "$c" "$map"
    # nm -D -S --with-symbol-versions: "ADDR [SIZE] TYPE NAME[@@VERSION]"; A = a version node.
    nm -D --defined-only -S --with-symbol-versions "$src" |
      awk -v lib="$n" -v c="$c" -v map="$map" -v imports="$work/imports" \
        -v defined="$work/defined" -v benign="$benign" '
        function hex(s,  v, i) {  # POSIX awk (mawk) has no strtonum
          v = 0
          for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789abcdef", tolower(substr(s, i, 1))) - 1
          return v
        }
        BEGIN {
          while ((getline s < imports) > 0) {
            base = s; ver = ""
            if (index(s, "@")) { base = substr(s, 1, index(s, "@") - 1); ver = substr(s, index(s, "@") + 1) }
            if (ver == "") unversioned[base] = 1; else wanted[base "@" ver] = 1
          }
          while ((getline s < defined) > 0) elsewhere[s] = 1
          while ((getline s < benign) > 0) { split(s, w, " "); if (w[1] == lib) quiet[w[2]] = 1 }
          print "/* A stub of " lib " made by scripts/bundle.sh. */" > c
          print "#include <stdio.h>\n#include <stdlib.h>" > c
          print "static char zero[4096] __attribute__((aligned(64)));" > c
          print "static void stub_called(const char* symbol) {" > c
          print "  const char* trace = getenv(\"HDRC_STUB_TRACE\");" > c
          print "  FILE* f = trace && *trace ? fopen(trace, \"a\") : NULL;" > c
          print "  if (f) {\n    fprintf(f, \"" lib " %s\\n\", symbol);\n    fclose(f);\n    return;\n  }" > c
          print "  fprintf(stderr, \"hdrconform bundle: %s called in " lib ", a stub (scripts/bundle.sh; bundle again with --no-stubs)\\n\", symbol);" > c
          print "  abort();\n}" > c
          nf = 0; nd = 0
        }
        {
          type = $(NF - 1); name = $NF; size = (NF == 4) ? hex($2) : 0
          if (type == "A") next
          ver = ""; base = name
          if (index(name, "@@")) { base = substr(name, 1, index(name, "@@") - 1); ver = substr(name, index(name, "@@") + 2) }
          else if (index(name, "@")) next  # a non-default (old) version: never linked against
          if (ver != "" && (base "@" ver) in wanted) {}
          else if ((base in unversioned) && !(base in elsewhere)) {}
          else next
          if (ver != "") nodes[ver] = nodes[ver] " " base ";"
          if (type ~ /^[TtWi]$/) {
            body = (base in quiet) ? "" : sprintf("stub_called(\"%s\"); ", base)
            printf "void* stub_f%d(void) __asm__(\"%s\");\nvoid* stub_f%d(void) { %sreturn zero; }\n", nf, base, nf, body > c
            nf++
          } else {
            if (size < 8) size = 8
            printf "__attribute__((aligned(16))) char stub_d%d[%d] __asm__(\"%s\");\n", nd, size, base > c
            nd++
          }
        }
        END {
          for (v in nodes) printf "%s {\n  global:%s\n};\n", v, nodes[v] > map
          printf "%d %d\n", nf, nd
        }' >"$work/$n.count"
    read -r nfunc ndata <"$work/$n.count"
    flags=(-shared -fPIC -O1 -o "$out/lib/$n" "-Wl,-soname,$n" "$c")
    [ -s "$map" ] && flags+=("-Wl,--version-script=$map")
    cc "${flags[@]}"
    printf '  %s  %d functions (%d return at once), %d objects (for %s)\n' "$n" "$nfunc" \
      "$(awk -v l="$n" '$1 == l' "$benign" | sort -u | wc -l)" "$ndata" "$src" >>"$work/stubs.txt"
  done
}

# The data the binary reads (core/install_paths.h).
share="$out/share/hdrconform"
cp -R "$root/cases" "$share/cases"
cp -R "$root/goldens" "$share/goldens"
cp -R "$root/gpu/shaders" "$share/shaders"
# The real-GPU check (scripts/gpu-check.py) and the planted shader defects it runs.
cp "$root/runner/planted_shader_defects.json" "$share/planted_shader_defects.json"
cp "$root/scripts/gpu-check.py" "$out/gpu-check"
commit="$(git -C "$root" rev-parse HEAD 2>/dev/null || echo unknown)"
if [ "$commit" != unknown ] &&
  [ -n "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ]; then
  commit="$commit-dirty"  # as runner/provenance.cpp records a modified tree
fi
echo "$commit" >"$share/source_commit"

cat >"$out/hdrconform" <<'EOF'
#!/bin/sh
# hdrconform bundle launcher (scripts/bundle.sh). Runs bin/hdrconform with the bundle's lib/ first
# on the library path, and lib/compat/ (libstdc++, libgcc_s) only where the host's are missing or
# older than the build's: the dynamic linker's trace (ld.so(8), LD_TRACE_LOADED_OBJECTS) then says
# "not found" (a library, or a symbol version such as GLIBCXX_3.4.30). The binary takes both out of LD_LIBRARY_PATH again for the commands it starts.
self="$(readlink -f "$0" 2>/dev/null || echo "$0")"
here="$(CDPATH='' cd -- "$(dirname -- "$self")" && pwd -P)" || exit 127
lib="$here/lib"
if LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" LD_TRACE_LOADED_OBJECTS=1 \
  "$here/bin/hdrconform" 2>&1 | grep -q -e 'not found' -e 'no version information'; then
  lib="$lib:$here/lib/compat"
fi
HDRC_BUNDLE_LIB="$lib"
LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export HDRC_BUNDLE_LIB LD_LIBRARY_PATH
exec "$here/bin/hdrconform" "$@"
EOF
chmod +x "$out/hdrconform"

# Which stub functions does a normal run call? OpenImageIO creates every plugin and asks every
# format library for its version when it first lists its plugins (pvt::catalog_all_plugins), and
# has static objects of some (dcmtk's DiRegister) made at load and destroyed at exit. The stubs are
# made in trace mode, the bundle reads and writes EXR and PNG (lut convert and info, a reference
# run of one case with its golden and report), and the functions called become the benign ones.
: >"$work/benign"
if [ ${#stub[@]} -gt 0 ]; then
  make_stubs /dev/null
  ex="$work/exercise"
  mkdir -p "$ex"
  cube="$root/cases/lut/cube/pq_identity_33.cube"
  (
    export HDRC_STUB_TRACE="$work/benign"
    first="$("$out/hdrconform" list | head -n 1)"
    "$out/hdrconform" lut convert "$cube" --to strip --format exr --out "$ex/strip.exr"
    "$out/hdrconform" lut convert "$cube" --to strip --format png16 --out "$ex/strip.png"
    "$out/hdrconform" lut info "$ex/strip.exr"
    "$out/hdrconform" lut info "$ex/strip.png"
    "$out/hdrconform" run --engine reference --filter "=$first" --images all --out "$ex/out"
  ) >"$work/exercise.log" 2>&1 || { cat "$work/exercise.log" >&2; exit 1; }
  make_stubs "$work/benign"
  {
    echo
    echo "stubs (lib/): a function aborts with its name if called, except those a normal run"
    echo "calls (counted below), which return zeroed memory:"
    cat "$work/stubs.txt"
  } >>"$manifest"
fi

# It must resolve every library but glibc's from the bundle, start, and see its cases.
outside="$(LD_LIBRARY_PATH="$out/lib:$out/lib/compat" ldd "$out/bin/hdrconform" |
  awk -v lib="$out/lib/" -v glibc="$glibc" '
    $2 == "=>" && !index(glibc, " " $1 " ") && ($3 == "not" || index($3, lib) != 1)')"
if [ -n "$outside" ]; then
  printf 'bundle: libraries not in the bundle:\n%s\n' "$outside" >&2
  exit 1
fi
"$out/hdrconform" pipelines >/dev/null
cases="$("$out/hdrconform" list | wc -l)"

mb() { du -sk "$@" | awk '{s += $1} END {printf "%.1f", s * 1024 / 1e6}'; }
{
  echo
  echo "sizes (MB): total $(mb "$out"), bin $(mb "$out/bin"), lib $(mb "$out/lib"), share $(mb "$share")"
} >>"$manifest"
echo "bundle: $out: $(mb "$out") MB (bin $(mb "$out/bin"), lib $(mb "$out/lib") with" \
  "${#real[@]} libraries and ${#stub[@]} stubs, share $(mb "$share")); $cases cases"
echo "bundle: largest libraries:"
find "$out/lib" -type f -printf '%s %P\n' | sort -rn | head -5 |
  awk '{printf "  %6.1f MB  %s\n", $1 / 1e6, $2}'
