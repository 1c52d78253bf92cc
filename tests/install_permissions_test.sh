#!/usr/bin/env bash
# An install under umask 000 leaves no world- or group-writable folder or
# file (cmake/install.cmake gives folders 0755 explicitly).
# Usage: install_permissions_test.sh BUILD_DIR
set -euo pipefail
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
(umask 000 && cmake --install "$1" --prefix "$prefix/usr" >"$prefix/install.log" 2>&1) ||
  { cat "$prefix/install.log"; exit 1; }
[[ -d $prefix/usr/share/railcosim/scenes ]] || { echo "nothing installed"; exit 1; }
writable=$(find "$prefix/usr" -perm /022 ! -type l)
[[ -z $writable ]] || { echo "writable by others after an install under umask 000:"; echo "$writable"; exit 1; }
echo "install under umask 000: $(find "$prefix/usr" -type d | wc -l) folders, none writable by others"
