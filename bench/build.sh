#!/bin/sh
# Builds the benchmark's C++ tools into bench/build/ (Release).
set -eu
bench_dir=$(cd "$(dirname "$0")" && pwd)
PATH=/usr/bin:$PATH cmake -S "$bench_dir" -B "$bench_dir/build" -DCMAKE_BUILD_TYPE=Release
PATH=/usr/bin:$PATH cmake --build "$bench_dir/build" --parallel 2
