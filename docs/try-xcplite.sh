#!/usr/bin/env bash
# Build Vector's XCPlite (MIT, not part of this repository) outside the repository and run the workbench against
# its hello_xcp example over XCP on UDP: the commands of docs/slave-profiles.md "Trying a real third-party slave".
#
#   docs/try-xcplite.sh [SOURCE] [PORT]
#
# SOURCE: a git URL or a local clone/bare repository of XCPlite (default: https://github.com/vectorgrp/XCPlite);
# PORT: the UDP port hello_xcp listens on (default 43110). Work happens in $XCPLITE_WORK (default /tmp/xcplite-try).
# Exits non-zero at the first command that fails; stops hello_xcp (by its PID) on the way out.
set -euo pipefail

source=${1:-https://github.com/vectorgrp/XCPlite}
port=${2:-43110}
work=${XCPLITE_WORK:-/tmp/xcplite-try}
workbench=${WORKBENCH:-workbench}

mkdir -p "$work"
if [ ! -d "$work/src" ]; then
    git clone --quiet --depth 1 "$source" "$work/src"
fi
cd "$work/src"
sed -i "s/OPTION_SERVER_PORT [0-9]* /OPTION_SERVER_PORT $port /" examples/hello_xcp/src/main.c
cmake -DCMAKE_BUILD_TYPE=Release -S . -B build >"$work/cmake.log"
make -C build hello_xcp >"$work/make.log"

run="$work/hello"
rm -rf "$run" && mkdir -p "$run" && cd "$run"
cp "$work/src/XCP_104.aml" .
"$work/src/build/hello_xcp" >"$run/hello_xcp.log" 2>&1 &
slave=$!
trap 'kill "$slave" 2>/dev/null || true' EXIT
sleep 1

set -x
# The demo's A2L (EPK mismatch: read-only) is enough to upload XCPlite's own (GET_ID 4), which it writes on CONNECT.
$workbench info --host 127.0.0.1 --port "$port" --save-a2l "$run/uploaded.a2l" >/dev/null
a2l=$(ls hello_xcp_*.a2l)
cmp "$a2l" "$run/uploaded.a2l"                                  # the same bytes as the file it wrote
E=(--a2l "$a2l" --host 127.0.0.1 --port "$port")
$workbench info "${E[@]}"
$workbench measure global_counter counter t1 --duration 0.5 --rate 5 "${E[@]}"
$workbench measure global_counter t1 heat_power --daq --duration 0.5 --json "${E[@]}" | tail -n 2
$workbench record "$run/rec.mf4" global_counter t1 heat_power --duration 5 "${E[@]}"
$workbench cal list "${E[@]}"
$workbench cal set params.flow_rate 0.5 "${E[@]}"
$workbench cal page reference "${E[@]}"
$workbench cal get params.flow_rate "${E[@]}"
$workbench cal page working "${E[@]}"
$workbench cal save "$run/params.dcm" "${E[@]}"
$workbench cal set params.flow_rate 0.25 "${E[@]}"
$workbench cal load "$run/params.dcm" "${E[@]}"
$workbench cal get params.flow_rate "${E[@]}"
