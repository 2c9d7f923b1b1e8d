/* flat_cube.h - a unit cube centred on the origin as OBJ text, for the tests and benchmarks that show
 * light diffusing around an edge, and a slab (1 x 1 x 0.06) for light through a thin part. Shared by
 * the tests and bench/bench_trade.c. */
#ifndef LUCENT_FLAT_CUBE_H
#define LUCENT_FLAT_CUBE_H

/* Wound outward; each face names its own normal, so the importer keeps the faces' vertices apart and
 * the normals flat (no smoothing across the edges). */
static const char flat_cube_obj[] = "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
                                    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
                                    "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n"
                                    "f 2//1 3//1 7//1\nf 2//1 7//1 6//1\nf 1//2 5//2 8//2\nf 1//2 8//2 4//2\n"
                                    "f 4//3 8//3 7//3\nf 4//3 7//3 3//3\nf 1//4 2//4 6//4\nf 1//4 6//4 5//4\n"
                                    "f 5//5 6//5 7//5\nf 5//5 7//5 8//5\nf 1//6 4//6 3//6\nf 1//6 3//6 2//6\n";

/* The slab: 50 mm x 50 mm x 3 mm at scale_mm 50, faces as the cube's. */
static const char flat_slab_obj[] = "v -0.5 -0.5 -0.03\nv 0.5 -0.5 -0.03\nv 0.5 0.5 -0.03\nv -0.5 0.5 -0.03\n"
                                    "v -0.5 -0.5 0.03\nv 0.5 -0.5 0.03\nv 0.5 0.5 0.03\nv -0.5 0.5 0.03\n"
                                    "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n"
                                    "f 2//1 3//1 7//1\nf 2//1 7//1 6//1\nf 1//2 5//2 8//2\nf 1//2 8//2 4//2\n"
                                    "f 4//3 8//3 7//3\nf 4//3 7//3 3//3\nf 1//4 2//4 6//4\nf 1//4 6//4 5//4\n"
                                    "f 5//5 6//5 7//5\nf 5//5 7//5 8//5\nf 1//6 4//6 3//6\nf 1//6 3//6 2//6\n";

#endif
