#!/usr/bin/env bash
# Copies the shared libraries that the binaries in BINDIR name (glibc's and
# the C++ runtime's excepted: the GPU host has its own) into LIBDIR, for
# carrying binaries built here to the GPU host (gpu-pdf-deps.sh,
# gpu-text-deps.sh).
#
#   scripts/carry-libs.sh BINDIR LIBDIR
set -euo pipefail
for bin in "$1"/*; do
  ldd "$bin" | awk '$3 ~ /^\// {print $3}'
done | sort -u | grep -vE '/(libc|libm|libdl|libpthread|librt|libgcc_s|libstdc\+\+)\.so' | while read -r lib; do
  cp -L "$lib" "$2/"
done
