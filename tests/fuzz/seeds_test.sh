#!/usr/bin/env bash
# The committed fuzz seeds are what make_fuzz_seeds writes today: a change
# of the protocol or of a session's messages that leaves them stale fails
# here (regenerate: make_fuzz_seeds scenes/soil.toml tests/fuzz/corpus).
# Other files of the corpus (inputs the fuzzer found) are left alone.
# Usage: seeds_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
fresh=$(mktemp -d)
trap 'rm -rf "$fresh"' EXIT
"$1/make_fuzz_seeds" "$2/scenes/soil.toml" "$fresh" >/dev/null
count=0
for seed in "$fresh"/*; do
  name=$(basename "$seed")
  cmp -s "$seed" "$2/tests/fuzz/corpus/$name" ||
    { echo "tests/fuzz/corpus/$name is stale: regenerate with make_fuzz_seeds scenes/soil.toml tests/fuzz/corpus"; exit 1; }
  count=$((count + 1))
done
[[ $count -ge 5 ]] || { echo "make_fuzz_seeds wrote $count seeds, expected at least 5"; exit 1; }
echo "$count seeds current"
