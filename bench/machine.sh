#!/usr/bin/env bash
# One line naming the processor the benchmarks ran on: model name, family and model numbers,
# nominal clock, second-level cache per core, the widest vector extension, and the core count.
# The same VM has run on processors of different generations; every benchmark table prints this
# line so that its figures can be told apart (docs/performance.md, *Machine*).
set -euo pipefail
field() { sed -n "s/^$1[[:space:]]*: *//p" /proc/cpuinfo 2>/dev/null | head -n 1; }
name=$(field 'model name')
family=$(field 'cpu family')
model=$(field 'model')
mhz=$(field 'cpu MHz')
l2=$(lscpu 2>/dev/null | sed -n 's/^L2 cache: *//p' | head -n 1)
flags=" $(field flags) "
vec=none
for v in sse2 avx avx2 avx512f; do [[ $flags == *" $v "* ]] && vec=$v; done
printf 'machine: %s (family %s, model %s), %.0f MHz, L2 %s, %s, %s cores\n' \
  "${name:-unknown}" "${family:-?}" "${model:-?}" "${mhz:-0}" "${l2:-?}" "$vec" "$(nproc)"
