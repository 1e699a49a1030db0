#!/usr/bin/env bash
# The service install target: the daemon, its unit, its sysusers file and its configs land
# where systemd and the daemon read them (under DESTDIR here); the unit passes
# `systemd-analyze verify` and its hardening scores at most 3.0 of 10 exposure.
set -euo pipefail
build=$1
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
DESTDIR="$dest" cmake --install "$build" --component service > /dev/null
unit=$(find "$dest" -name topostationd.service)
test -x "$(find "$dest" -name topostationd -type f)"
test -f "$(find "$dest" -path '*sysusers.d/topostation.conf')"
test -f "$dest/etc/topostation/daemon.yaml"
test -f "$dest/etc/topostation/rig.yaml"
if grep -q '@TS_' "$unit"; then echo "unsubstituted template variable in $unit"; exit 1; fi
grep -q '^Type=notify$' "$unit"
grep -q '^WatchdogSec=' "$unit"
grep -q '^StateDirectory=topostationd$' "$unit"
# verify resolves ExecStart on this machine: point it at the daemon just built.
sed -i "s#^ExecStart=[^ ]*/topostationd #ExecStart=$build/station/topostationd #" "$unit"
systemd-analyze verify "$unit"
systemd-analyze security --offline=yes --threshold=30 "$unit" > /dev/null
echo "service install: ok"
