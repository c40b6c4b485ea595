#!/bin/sh
# Starts ddsimp-server, adding --config for a configuration file mounted at
# $DDSIMP_CONFIG_FILE (default /etc/ddsimp/ddsimp.conf) if there is one. exec: the server
# replaces this shell and receives SIGTERM itself.
set -eu
config="${DDSIMP_CONFIG_FILE:-/etc/ddsimp/ddsimp.conf}"
if [ -f "$config" ]; then
    exec /usr/local/bin/ddsimp-server --config "$config" "$@"
fi
exec /usr/local/bin/ddsimp-server "$@"
