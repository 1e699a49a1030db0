#!/usr/bin/env bash
# The udev install target puts both rule files where udev reads them (under DESTDIR here),
# with the stage adapter's ids filled in and ModemManager kept away from it.
set -euo pipefail
build=$1
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
DESTDIR="$dest" cmake --install "$build" --component udev > /dev/null
rules="$dest/etc/udev/rules.d"
test -f "$rules/60-topostation-cameras.rules"
stage="$rules/61-topostation-stage.rules"
grep -q 'ATTRS{idVendor}=="[0-9a-f]\{4\}", ATTRS{idProduct}=="[0-9a-f]\{4\}"' "$stage"
grep -q 'SYMLINK+="topostation-stage"' "$stage"
grep -q 'ENV{ID_MM_DEVICE_IGNORE}="1"' "$stage"
if grep -q '@TS_' "$stage"; then echo "unsubstituted template variable in $stage"; exit 1; fi
grep -q 'TAG+="uaccess"' "$rules/60-topostation-cameras.rules"
echo "udev rules install: ok"
