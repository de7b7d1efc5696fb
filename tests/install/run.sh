#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds a consumer with find_package(proprio).
set -euo pipefail
build=$1 src=$2
prefix=$(mktemp -d) work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
test -x "$prefix/bin/proprio"
"$prefix/bin/proprio" --version
cmake -S "$src/tests/install/consumer" -B "$work" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work" >/dev/null
"$work/consumer"
