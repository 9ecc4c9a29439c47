#!/usr/bin/env bash
# Minimises one harness's corpus (tests/fuzz/README.md): libFuzzer's -set_cover_merge=1 over
# tests/fuzz/corpus/NAME/ and any further directories given (a campaign's finds, say), with
# tests/fuzz/regressions/NAME/ as the initial corpus, so that nothing the regression inputs
# already cover is kept twice. The result replaces tests/fuzz/corpus/NAME/: inputs are named by
# their SHA-1 as libFuzzer writes them, except that an input which had another name keeps it.
# Prints files, bytes, cov and ft (corpus and regressions replayed together) before and after;
# for the harnesses with threads (cli, search, c_api) cov and ft vary by a few between replays.
# Review and commit with `git add -A tests/fuzz/corpus/NAME`.
#
#   scripts/fuzz-minimise.sh NAME [DIR...]
#   e.g. scripts/fuzz-minimise.sh cli build-fuzz/campaign/cli/corpus
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
    echo "usage: scripts/fuzz-minimise.sh NAME [DIR...]" >&2
    exit 2
fi
name="$1"
shift
root="$PWD"
corpus="$root/tests/fuzz/corpus/$name"
regressions="$root/tests/fuzz/regressions/$name"
fuzzer="$root/build-fuzz/tests/fuzz/${name}_fuzzer"
flags=(-rss_limit_mb=2048 -timeout=10 -close_fd_mask=3)
[ -d "$corpus" ] || { echo "no corpus $corpus" >&2; exit 2; }
# Absolute paths throughout: cli_fuzzer works in a scratch directory of its own.
extra=()
for dir in "$@"; do
    extra+=("$(cd "$dir" && pwd)")
done
seeds=()
if [ -d "$regressions" ]; then
    seeds=("$regressions")
fi

bash scripts/fuzz-build.sh

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# One replay: "files bytes cov ft" of the directories given.
measure() {
    local files bytes line
    files=$(find "$@" -type f | wc -l)
    bytes=$(find "$@" -type f -exec cat {} + | wc -c)
    line=$("$fuzzer" "${flags[@]}" -runs=0 "$@" 2>&1 | grep INITED || true)
    echo "files $files, bytes $bytes, cov $(echo "$line" | grep -o 'cov: [0-9]*' | cut -d' ' -f2)," \
        "ft $(echo "$line" | grep -o 'ft: [0-9]*' | cut -d' ' -f2)"
}
before=$(measure "$corpus" "${extra[@]}" "${seeds[@]}")

mkdir "$work/merged"
if [ -d "$regressions" ]; then
    cp "$regressions"/* "$work/merged/"
fi
"$fuzzer" "${flags[@]}" -set_cover_merge=1 "$work/merged" "$corpus" "${extra[@]}" \
    >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
grep 'MERGE-OUTER: .* new files' "$work/log" || true
if [ -d "$regressions" ]; then
    for file in "$regressions"/*; do
        rm -f "$work/merged/$(basename "$file")"
    done
fi
# Inputs of the old corpus with a name of their own (not a SHA-1) keep it.
for file in "$corpus"/*; do
    base="$(basename "$file")"
    if ! [[ "$base" =~ ^[0-9a-f]{40}$ ]]; then
        hash="$(sha1sum <"$file" | cut -d' ' -f1)"
        if [ -f "$work/merged/$hash" ]; then
            mv "$work/merged/$hash" "$work/merged/$base"
        fi
    fi
done
find "$corpus" -mindepth 1 -delete
cp "$work/merged"/* "$corpus/"

echo "$name before: $before (corpus${extra:+, the extra directories} and regressions)"
echo "$name after:  $(measure "$corpus" "${seeds[@]}") (corpus and regressions)"
