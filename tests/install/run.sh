#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds, from outside the tree, a consumer
# that finds the package with find_package(proprio), links every module and runs one call of
# each (a headless render among them) with the installed data; and a program of proprio::topics
# alone, whose link line must name neither MuJoCo nor OpenCV.
set -euo pipefail
build=$1 src=$2
prefix=$(mktemp -d) work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
test -x "$prefix/bin/proprio"
test -f "$prefix/share/proprio/objects/catalogue.json"
test -f "$prefix/share/proprio/models/arm.xml"
# The installed CLI finds the installed data beside it (no environment, no source tree).
env -u PROPRIO_DATA_DIR "$prefix/bin/proprio" --version
env -u PROPRIO_DATA_DIR "$prefix/bin/proprio" sim view --object mug --width 160 --height 120 \
  --out "$work/view.png"
test -s "$work/view.png"
cmake -S "$src/tests/install/consumer" -B "$work" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work" -j 2 >/dev/null
# The consumer lives outside the prefix: it is told where the installed data is.
PROPRIO_DATA_DIR="$prefix/share/proprio" "$work/consumer"
"$work/topics_only"
link=$(find "$work" -path '*topics_only.dir/link.txt' | head -1)
test -n "$link"
if grep -Eiq 'mujoco|opencv' "$link"; then
  echo "topics_only links MuJoCo or OpenCV: $(cat "$link")" >&2
  exit 1
fi
if readelf -d "$work/topics_only" | grep -Eiq 'mujoco|opencv'; then
  echo "topics_only needs MuJoCo or OpenCV at run time" >&2
  exit 1
fi
# The Python package, when it was built: importable from the prefix's dist-packages by
# /usr/bin/python3, with the installed data (docs/python.md).
pydir=$(find "$prefix/lib" -maxdepth 3 -type d -path '*/dist-packages/proprio' | head -1)
if [ -n "$pydir" ]; then
  (cd "$work" && PYTHONPATH=$(dirname "$pydir") PROPRIO_DATA_DIR="$prefix/share/proprio" \
    /usr/bin/python3 -c "import proprio, proprio.sim; assert proprio.__file__.startswith('$prefix'); \
print(len(proprio.sim.catalogue_names()), 'catalogue objects from the installed package')")
fi
echo "install: every module linked and ran; topics_only links neither MuJoCo nor OpenCV"
