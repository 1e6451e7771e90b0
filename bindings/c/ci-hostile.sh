#!/usr/bin/env bash
# The C API's hostile-input tier (issue 37): bindings/c/tests/hostile.c,
# linked with the static library cargo builds (test profile), run twice;
# every call must return its documented code, and nothing may abort.
#
#  1. -fsanitize=address,undefined. ASan reserves terabytes of shadow
#     address space, so it cannot run under `ulimit -v`; its allocator
#     refuses any one allocation over 3 GiB instead (returning NULL, which
#     the library's fallible allocations report), and checks leaks.
#  2. -fsanitize=undefined under `ulimit -v` 6 GiB: the suite's inputs (up
#     to 4 GiB each, mapped without touching their pages) fit, a second
#     copy of one does not.
#
# 22 to 30 s after the build on a 2-core AMD EPYC VM. Usage: bash bindings/c/ci-hostile.sh
# (CC picks the compiler: gcc or clang.)
set -euo pipefail
cd "$(dirname "$0")/../.."

cargo build --quiet -p micromap-index-capi --profile test --lib
lib=target/debug/libmicromap_index_capi.a
cc=${CC:-cc}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# `rustc --print native-static-libs` on Linux (docs/c.md).
libs=(-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc)
flags=(-std=c99 -Wall -Wextra -Werror -pedantic -g -fno-omit-frame-pointer
    -fno-sanitize-recover=undefined -Ibindings/c/include)
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1

echo "== C hostile inputs: ASan + UBSan, allocations over 3 GiB refused"
"$cc" "${flags[@]}" -fsanitize=address,undefined bindings/c/tests/hostile.c "$lib" \
    "${libs[@]}" -o "$work/hostile-asan"
ASAN_OPTIONS=allocator_may_return_null=1:max_allocation_size_mb=3072:detect_leaks=1 \
    timeout 600 "$work/hostile-asan" >"$work/asan.txt"
tail -n 1 "$work/asan.txt"

echo "== C hostile inputs: UBSan under ulimit -v 6 GiB"
"$cc" "${flags[@]}" -fsanitize=undefined bindings/c/tests/hostile.c "$lib" \
    "${libs[@]}" -o "$work/hostile-capped"
(ulimit -v $((6 << 20)) && timeout 600 "$work/hostile-capped" >"$work/capped.txt")
tail -n 1 "$work/capped.txt"

# The two runs answer every call alike, message for message.
diff "$work/asan.txt" "$work/capped.txt"
