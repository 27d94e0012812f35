#!/usr/bin/env bash
# `make run`: opens the app on the two-spheres phantom; with no display (or before the app is
# built in), prints the comparison instead.
set -euo pipefail
snert=$1
if "$snert" --help 2>&1 | grep -q "^  gui"; then
    if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
        exec "$snert" gui phantom:two-spheres
    fi
    out=snert-two-spheres.png
    echo "No display: writing a headless snapshot to $out"
    exec "$snert" render phantom:two-spheres --out "$out"
fi
exec "$snert" compare phantom:two-spheres
