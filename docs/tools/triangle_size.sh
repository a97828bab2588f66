#!/bin/sh
# The triangle-size study of docs/accuracy.md: S1's sphere at one screen size (960x540, the
# sphere about 300 px across), tessellated from 8 to 512 segments, every mode and both
# fast-Phong methods, one thread, at the baseline SIMD level and the best one.
# Prints one line per (segments, SIMD level, mode):
#   segments simd mode triangles_drawn pixels_shaded px_per_triangle median_ms ns_per_pixel ns_per_triangle fallbacks
# (fallbacks: the triangles a fast-Phong method handed back to `phong`; 0 for the other modes).
# Run from the repository root after `cargo build --release -p phosphor-cli`.
set -eu
bin=${PHOSPHOR:-target/release/phosphor}
frames=${FRAMES:-20}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
for s in 8 16 32 64 128 256 512; do
    scene="$dir/s$s.toml"
    sed "s/segments = 128, rings = 64/segments = $s, rings = $((s / 2))/" \
        assets/scenes/s1-sphere.toml > "$scene"
    for mode in flat gouraud fast-phong:fit fast-phong:taylor phong reference; do
        shading=${mode%%:*}
        method=${mode#*:}
        extra=""
        if [ "$shading" = fast-phong ]; then extra="--fast-phong $method"; fi
        # Triangles drawn, pixels shaded and fast-Phong fallbacks of this mode (one frame).
        line=$("$bin" render "$scene" --size 960x540 --shading "$shading" $extra --threads 1 \
            -o "$dir/frame.png" 2>&1)
        counts=$(echo "$line" | sed -n 's/.* \([0-9]*\) of [0-9]* triangles drawn, \([0-9]*\) pixels shaded.*/\1 \2/p')
        fallbacks=$(echo "$line" | sed -n 's/.* \([0-9]*\) fast-phong fallbacks.*/\1/p')
        for simd in baseline auto; do
            "$bin" bench "$scene" --size 960x540 --shading "$shading" $extra --threads 1 \
                --simd "$simd" --frames "$frames" |
                awk -v s="$s" -v simd="$simd" -v mode="$mode" -v counts="$counts" -v fb="${fallbacks:-0}" '{
                    split(counts, c, " ");
                    split($2, m, "=");
                    printf "%d %s %s %d %d %.1f %.3f %.1f %.1f %d\n", s, simd, mode, c[1], c[2],
                        c[2] / c[1], m[2], m[2] * 1e6 / c[2], m[2] * 1e6 / c[1], fb;
                }'
        done
    done
done
