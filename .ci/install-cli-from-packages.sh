#!/usr/bin/env bash
# Installs the CLI as a user would from crates.io, but offline and from this
# tree's packages: the published crates are packaged (`cargo package`), the
# .crate files are unpacked next to their vendored crates.io dependencies
# (`cargo vendor`), and `cargo install micromap-index-cli --offline --locked`
# builds it from that directory, which replaces crates.io. A file missing
# from a package, a path-only dependency or a lockfile that does not
# resolve fails here. Then the installed binary runs the README's first
# command and bakes and verifies a glTF with EXT_mesh_opacity_micromap.
#
# Only `cargo vendor` may touch the network (when the registry cache lacks a
# dependency). The build starts from scratch each time (a new directory
# source is a new source to cargo, so nothing stale can be reused): about
# one minute of CPU (measured: 1m01s user, 2-core x86_64).
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
published=(micromap-index micromap-index-assets micromap-index-conformance micromap-index-render micromap-index-cli-support micromap-index-cli)
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -1)
cargo package --allow-dirty --no-verify --quiet $(printf -- '-p %s ' "${published[@]}")
cargo vendor --versioned-dirs --quiet "$work/vendor" >/dev/null
for crate in "${published[@]}"; do
    file="target/package/$crate-$version.crate"
    tar -xzf "$file" -C "$work/vendor"
    # A directory source needs a checksum file; no per-file sums (the
    # package's own sum is what a registry would hold).
    printf '{"files":{},"package":"%s"}' "$(sha256sum "$file" | cut -d' ' -f1)" \
        > "$work/vendor/$crate-$version/.cargo-checksum.json"
done
cargo install --offline --locked --quiet --root "$work/root" --target-dir "$work/target" \
    --config "source.crates-io.replace-with='ci-packages'" \
    --config "source.ci-packages.directory='$work/vendor'" \
    micromap-index-cli
bin="$work/root/bin/micromap-index"
out=$(echo '{"u": "0.28", "v": "0.4", "level": 3}' | "$bin" eval --variant spec-real)
[ "$out" = '{"index":23}' ] || { echo "installed CLI: unexpected eval output: $out" >&2; exit 1; }
"$bin" bake --gltf assets/crytek-sponza/cards.glb --out "$work/bake" --gltf-out cards.glb \
    --level 3 --quiet --no-preview >/dev/null
"$bin" verify-bake --gltf "$work/bake/cards.glb"
echo "installed micromap-index-cli $version from its package, offline"
