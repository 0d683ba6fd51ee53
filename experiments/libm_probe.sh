#!/usr/bin/env bash
# Does glibc's libm give other last bits on a CPU without FMA/AVX2? Compiles a small C program
# that calls exp, log, sin, cos and pow 4 M times each over a fixed grid and prints an FNV-style
# hash of the result bits, then runs it as loaded and with the CPU features masked through
# GLIBC_TUNABLES (as glibc would see a CPU without AVX2, FMA and AVX-512). Two different hashes
# mean libm's run-time choice of implementation changes results, so no build of codesign that
# calls these functions can be bit-identical across such CPUs (docs/journal/results.md, "Pipeline check").
#   bash experiments/libm_probe.sh
set -euo pipefail
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/probe.c" <<'C'
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
int main(void) {
  uint64_t h = 0;
  double x = -20.0;
  for (int i = 0; i < 4000000; i++) {
    const double v[5] = {exp(x), log(fabs(x) + 1e-3), sin(x * 7.3), cos(x * 3.1), pow(fabs(x) + 0.5, 1.37)};
    for (int k = 0; k < 5; k++) {
      uint64_t b;
      memcpy(&b, &v[k], 8);
      h = h * 1099511628211ULL ^ b;
    }
    x += 1e-5;
  }
  printf("%016llx\n", (unsigned long long)h);
  return 0;
}
C
cc -O2 -fno-builtin "$dir/probe.c" -o "$dir/probe" -lm
echo "glibc $(ldd --version | head -1 | awk '{print $NF}'), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "as loaded:                 $("$dir/probe")"
echo "without AVX2, FMA, AVX512: $(GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F "$dir/probe")"
