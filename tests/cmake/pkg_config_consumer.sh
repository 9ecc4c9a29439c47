#!/usr/bin/env bash
# Builds and runs a program with the flags of an installed tricell's pkg-config file only, as a
# C or Fortran user without CMake does; PKG_CONFIG_LIBDIR is that prefix's alone, so no other
# tricell on the machine can stand in. The .pc file must name the licence, and the licence text
# must be installed beside the documentation.
#   pkg_config_consumer.sh PREFIX PACKAGE COMPILER SOURCE OUTPUT
set -euo pipefail
prefix="$1" package="$2" compiler="$3" source="$4" output="$5"

pc_file=$(find "$prefix" -name "$package.pc" -path '*/pkgconfig/*' | head -n 1)
if [ -z "$pc_file" ]; then
    echo "pkg_config_consumer: no $package.pc under $prefix" >&2
    exit 1
fi
if ! grep -qx 'License: BSD-3-Clause' "$pc_file"; then
    echo "pkg_config_consumer: $pc_file names no licence (License: BSD-3-Clause)" >&2
    exit 1
fi
if [ -z "$(find "$prefix" -path '*/doc/tricell/LICENSE')" ]; then
    echo "pkg_config_consumer: no doc/tricell/LICENSE under $prefix" >&2
    exit 1
fi
export PKG_CONFIG_LIBDIR="$(dirname "$pc_file")"
flags=$(pkg-config --cflags --libs "$package")
echo "pkg-config --cflags --libs $package: $flags"
# shellcheck disable=SC2086 # the flags are words
"$compiler" "$source" $flags -o "$output"
libdir=$(pkg-config --variable=libdir tricell)
LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$output"
