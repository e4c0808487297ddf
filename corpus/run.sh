#!/usr/bin/env bash
# Runs `cleave check` on every shipped deck of the corpus and prints PASS/FAIL with the first
# error line, then the totals. Run from anywhere; paths are taken relative to the repository root.
#   CLEAVE=path/to/cleave corpus/run.sh        (default: target/release/cleave)
set -u
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
cd "$root"
CLEAVE="${CLEAVE:-target/release/cleave}"
if [ ! -x "$CLEAVE" ]; then
    echo "cleave binary not found at $CLEAVE (build with: cargo build --release)" >&2
    exit 1
fi
# The main decks (files pulled in by *INCLUDE, such as pydyna/elementary/transform.k, are not
# decks of their own and are not listed).
decks=(
    corpus/decks/pydyna/test_thermal_stress.k
    corpus/decks/pydyna/elementary/test_elementary_main.k
    corpus/decks/cxh-1123-ls-dyna-ablation/test.k
)
pass=0; fail=0
for d in "${decks[@]}"; do
    out="$("$CLEAVE" check "$d" 2>&1)"; rc=$?
    if [ $rc -eq 0 ]; then
        pass=$((pass + 1)); printf 'PASS  %s\n' "$d"
    else
        fail=$((fail + 1))
        first="$(printf '%s\n' "$out" | grep -m1 -E '^error' || printf '%s\n' "$out" | head -n1)"
        printf 'FAIL  %s  (exit %d)\n      %s\n' "$d" "$rc" "$first"
    fi
done
printf '\n%d decks: %d pass, %d fail\n' $((pass + fail)) "$pass" "$fail"
