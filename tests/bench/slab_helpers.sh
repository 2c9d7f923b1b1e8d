# slab_helpers.sh - shell helpers of the benchmarks that score a slab's centre against method "path"
# (path_slabs.sh, path_exit_angles.sh): the slab mesh, the centre's mean colour, per-channel ratios. Sourced.
# shellcheck shell=bash

# write_slab_obj FILE HALF: tests/flat_cube.h's slab (a unit square across) with its half thickness HALF;
# corners, one normal per face, faces as the cube's
write_slab_obj() {
    awk -v h="$2" 'BEGIN {
        printf "v -0.5 -0.5 %s\nv 0.5 -0.5 %s\nv 0.5 0.5 %s\nv -0.5 0.5 %s\n", -h, -h, -h, -h
        printf "v -0.5 -0.5 %s\nv 0.5 -0.5 %s\nv 0.5 0.5 %s\nv -0.5 0.5 %s\n", h, h, h, h
        print "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1"
        print "f 2//1 3//1 7//1\nf 2//1 7//1 6//1\nf 1//2 5//2 8//2\nf 1//2 8//2 4//2"
        print "f 4//3 8//3 7//3\nf 4//3 7//3 3//3\nf 1//4 2//4 6//4\nf 1//4 6//4 5//4"
        print "f 5//5 6//5 7//5\nf 5//5 7//5 8//5\nf 1//6 4//6 3//6\nf 1//6 3//6 2//6"
    }' > "$1"
}

centre() {  # centre EXR: the mean R G B of the 3x3 centre pixels of a 9x9 image
    oiiotool "$1" --ch R,G,B --cut 3x3+3+3 --printinfo:stats=1 2>/dev/null | awk '/Stats Avg/ { print $3, $4, $5; exit }'
}

ratios() {  # ratios "r g b" "r g b" [DIGITS]: the first over the second, per channel (2 decimals by default)
    awk -v a="$1" -v b="$2" -v n="${3:-2}" 'BEGIN { split(a, x, " "); split(b, y, " "); f = "%." n "f";
        printf f " / " f " / " f, (y[1] > 0 ? x[1] / y[1] : 0), (y[2] > 0 ? x[2] / y[2] : 0), (y[3] > 0 ? x[3] / y[3] : 0) }'
}
