#!/usr/bin/env bash
# CTest `bundle`: scripts/bundle.sh makes a bundle that runs where neither the source tree nor the
# build tree exists, with its own libraries, cases, goldens and shaders.
#
#   runner/bundle_test.sh SOURCE_DIR BUILD_DIR
#
# The bundle is made, copied elsewhere and the original deleted; the copy is mounted read-only at
# another path in a bubblewrap sandbox that has /usr, /etc, the bundle and a scratch folder, with
# an empty tmpfs over the source and build trees and /dev/null over the host's copy of every
# library the bundle carries in lib/ (a library missing from the bundle cannot be found on the
# host). There, on lavapipe named through VK_DRIVER_FILES as a vendor's ICD would be:
#  - `list` shows every case the build's binary lists;
#  - `run` of the first two cases of every case folder (every pipeline) exits 0, checks them
#    against the bundle's goldens, and writes case images identical, byte for byte (but for their
#    time stamps), to the build's binary's run of the same cases; the pipeline cache lands in
#    $XDG_CACHE_HOME;
#  - a damaged PNG gives the build's error, not a stub's abort (try_all_readers off);
#  - planted: a stub function outside a normal run's (libtiff's TIFFOpen) aborts naming itself; a
#    host libstdc++ too old for the build (a fake one first on LD_LIBRARY_PATH) makes the
#    launcher add lib/compat.
set -euo pipefail
src="$(cd "$1" && pwd)"
build="$(cd "$2" && pwd)"
start=$SECONDS
fail() {
  echo "bundle_test: FAIL: $*" >&2
  exit 1
}
command -v bwrap >/dev/null || {
  echo "bundle_test: bwrap (bubblewrap) is missing: scripts/setup.sh installs it" >&2
  exit 1
}
icd=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
[ -f "$icd" ] || fail "no lavapipe ICD at $icd (mesa-vulkan-drivers)"

tmp="$(mktemp -d "${TMPDIR:-/tmp}/hdrc-bundle-test.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
"$src/scripts/bundle.sh" --out "$tmp/made" --build "$build" --no-build
cp -a "$tmp/made" "$tmp/moved"
rm -rf "$tmp/made"
mkdir -p "$tmp/run/cache" "$tmp/run/home" "$tmp/run/fake"

# The sandbox: the bundle read-only at /opt/hdrconform, the scratch folder at /scratch.
sandbox=(bwrap --die-with-parent --ro-bind /usr /usr --ro-bind /etc /etc --proc /proc --dev /dev
  --tmpfs /tmp --ro-bind "$tmp/moved" /opt/hdrconform --bind "$tmp/run" /scratch)
for d in /bin /sbin /lib /lib32 /lib64 /libx32; do
  if [ -L "$d" ]; then
    sandbox+=(--symlink "$(readlink "$d")" "$d")
  elif [ -d "$d" ]; then
    sandbox+=(--ro-bind "$d" "$d")
  fi
done
sandbox+=(--tmpfs "$src")
case "$build/" in "$src"/*) ;; *) sandbox+=(--tmpfs "$build") ;; esac
hidden=0
while read -r name path; do
  real="$(readlink -f "$path")"
  case "$real" in /usr/* | /lib*) sandbox+=(--ro-bind /dev/null "$real") hidden=$((hidden + 1)) ;; esac
done < <(sed -n '/^real libraries/,/^$/p' "$tmp/moved/MANIFEST.txt" | awk 'NF == 2' |
  grep -v -e '  libstdc++' -e '  libgcc_s')
[ "$hidden" -gt 5 ] || fail "only $hidden host libraries hidden (MANIFEST.txt format?)"
sandbox+=(--clearenv --setenv PATH /usr/bin:/bin --setenv HOME /scratch/home
  --setenv XDG_CACHE_HOME /scratch/cache --setenv VK_DRIVER_FILES "$icd" --chdir /scratch)
in_box() { "${sandbox[@]}" "$@"; }

# The source and build trees are out of reach.
in_box sh -c "test ! -e '$src/cases' && test ! -e '$build/runner/hdrconform'" ||
  fail "the sandbox still sees the source or build tree"

# Every case.
"$build/runner/hdrconform" list >"$tmp/list.build"
in_box /opt/hdrconform/hdrconform list >"$tmp/run/list.bundle" || fail "list failed in the bundle"
cmp -s "$tmp/list.build" "$tmp/run/list.bundle" || fail "the bundle lists other cases than the build"
total="$(wc -l <"$tmp/run/list.bundle")"
echo "bundle_test: list: $total cases, as the build's binary"

# The real-GPU check finds the bundle's own launcher, shaders and planted defects (run outside the
# box: the box hides the host's libz, which python3 needs).
if command -v python3 >/dev/null; then
  COLUMNS=100000 "$tmp/moved/gpu-check" --help >"$tmp/gpu-check.help" 2>&1 ||
    fail "gpu-check --help failed: $(cat "$tmp/gpu-check.help")"
  for f in hdrconform share/hdrconform/shaders share/hdrconform/planted_shader_defects.json; do
    grep -qF "default: $tmp/moved/$f)" "$tmp/gpu-check.help" ||
      fail "gpu-check's default is not the bundle's $f"
  done
  echo "bundle_test: gpu-check finds the bundle's launcher, shaders and planted defects"
fi

# Two cases of every folder, every pipeline among them.
filter="$(awk -F/ 'n[$1]++ < 2 {printf "%s=%s", sep, $0; sep = ","}' "$tmp/run/list.bundle")"
picked="$(echo "$filter" | tr ',' '\n' | wc -l)"
rc=0
in_box /opt/hdrconform/hdrconform run --filter "$filter" --out /scratch/out -j 2 --images all \
  >"$tmp/run/run.log" 2>&1 || rc=$?
cat "$tmp/run/run.log"
[ "$rc" = 0 ] || fail "run in the bundle exited $rc"
results="$tmp/run/out/results.json"
grep -q '"dir": *"/opt/hdrconform/share/hdrconform/goldens"' "$results" ||
  fail "results.json does not name the bundle's goldens"
checked="$(grep -o '"checked": *[0-9]*' "$results" | grep -o '[0-9]*$')"
match="$(grep -o '"match": *[0-9]*' "$results" | grep -o '[0-9]*$')"
[ "${checked:-0}" -gt 0 ] && [ "$checked" = "$match" ] ||
  fail "goldens: ${match:-?} of ${checked:-?} match"
for p in ue55 unity_urp operators pq_grading; do
  grep -q "\"pipeline\": *\"$p\"" "$results" || fail "no case of pipeline $p ran"
done
grep -q '/opt/hdrconform/share/hdrconform/shaders' "$results" ||
  fail "results.json does not name the bundle's shaders"
commit="$(cat "$tmp/moved/share/hdrconform/source_commit")"
grep -q "\"$commit\"" "$results" || fail "results.json does not record the commit $commit"
[ -s "$tmp/run/cache/hdrconform/vk_pipeline_cache.bin" ] ||
  fail "no pipeline cache in XDG_CACHE_HOME"
echo "bundle_test: run: $picked cases, goldens $match/$checked match"

# The same cases by the build's binary: the same images, byte for byte but for the time OpenImageIO
# writes into each (the EXR attribute DateTime, "YYYY:MM:DD hh:mm:ss").
"$build/runner/hdrconform" run --filter "$filter" --out "$tmp/out.build" -j 2 --images all \
  >/dev/null 2>&1 || fail "the build's binary failed the cases"
undated() { LC_ALL=C sed -E 's/[0-9]{4}:[0-9]{2}:[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2}/DATETIME/g' "$1"; }
images=0
while IFS= read -r f; do
  [ -f "$tmp/run/out/cases/$f" ] || fail "the bundle wrote no cases/$f"
  cmp -s <(undated "$tmp/out.build/cases/$f") <(undated "$tmp/run/out/cases/$f") ||
    fail "cases/$f differs between the bundle's run and the build's"
  images=$((images + 1))
done < <(cd "$tmp/out.build/cases" && find -L . -type f | sed 's|^\./||')
bundle_images="$(cd "$tmp/run/out/cases" && find -L . -type f | wc -l)"
[ "$images" -gt "$picked" ] && [ "$images" = "$bundle_images" ] ||
  fail "$images case files from the build, $bundle_images from the bundle"
echo "bundle_test: $images case files identical to the build's run"

# A damaged PNG: the build's error, not a stub's abort.
head -c 4096 /dev/zero | tr '\0' 'x' >"$tmp/run/damaged.png"
"$build/runner/hdrconform" lut info "$tmp/run/damaged.png" >/dev/null 2>"$tmp/err.build" || true
sed -i "s|$tmp/run|/scratch|g" "$tmp/err.build"
rc=0
in_box /opt/hdrconform/hdrconform lut info /scratch/damaged.png >/dev/null 2>"$tmp/err.bundle" || rc=$?
[ "$rc" = 2 ] || fail "lut info of a damaged PNG exited $rc in the bundle (2 expected)"
cmp -s "$tmp/err.build" "$tmp/err.bundle" ||
  fail "a damaged PNG: '$(cat "$tmp/err.bundle")' in the bundle, '$(cat "$tmp/err.build")' built"

# Planted: a stubbed function that a normal run never calls aborts, naming itself.
printf 'void* TIFFOpen(const char*, const char*);\nint main(void) { return TIFFOpen("x", "r") != 0; }\n' \
  >"$tmp/tiff.c"
cc -o "$tmp/run/tiff" "$tmp/tiff.c" "$tmp/moved/lib/libtiff.so.6"
rc=0
in_box env LD_LIBRARY_PATH=/opt/hdrconform/lib /scratch/tiff 2>"$tmp/err.tif" || rc=$?
[ "$rc" != 0 ] && grep -q 'TIFFOpen called in libtiff.so.6, a stub' "$tmp/err.tif" ||
  fail "libtiff's stub TIFFOpen did not abort (exit $rc: $(cat "$tmp/err.tif"))"

# Planted: a host libstdc++ without the build's symbol versions.
# An old libstdc++ as the dynamic linker sees one: its first symbol versions, none of GCC 12's.
printf 'int hdrc_fake_a;\nint hdrc_fake_b;\n' >"$tmp/fake.c"
printf 'GLIBCXX_3.4 { global: hdrc_fake_a; local: *; };\nCXXABI_1.3 { global: hdrc_fake_b; };\n' \
  >"$tmp/fake.map"
cc -shared -fPIC -o "$tmp/run/fake/libstdc++.so.6" -Wl,-soname,libstdc++.so.6 \
  "-Wl,--version-script=$tmp/fake.map" "$tmp/fake.c"
in_box env LD_LIBRARY_PATH=/opt/hdrconform/lib:/scratch/fake /opt/hdrconform/bin/hdrconform \
  pipelines >/dev/null 2>&1 && fail "the fake libstdc++ was not used (the planted defect is not planted)"
in_box env LD_LIBRARY_PATH=/scratch/fake /opt/hdrconform/hdrconform pipelines >/dev/null ||
  fail "the launcher did not fall back to lib/compat"

echo "bundle_test: pass ($((SECONDS - start)) s; $hidden host libraries hidden)"
