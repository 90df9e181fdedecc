#!/bin/sh
# A python3 that cannot import matplotlib (-S: no site, so no dist-packages), for the test that
# `hil fly --out` warns, names python3-matplotlib and keeps its exit status without it.
if [ -x /usr/bin/python3 ]; then exec /usr/bin/python3 -S "$@"; fi
exec python3 -S "$@"
