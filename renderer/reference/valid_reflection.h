/* valid_reflection.h - Blender Cycles' correction of a shading normal at grazing views (its
 * ensure_valid_reflection), for method "path" with boundary "cycles". */
#ifndef LUCENT_VALID_REFLECTION_H
#define LUCENT_VALID_REFLECTION_H

/* The shading normal Cycles gives a closure seen from unit direction i (towards the eye) on a surface with
 * unit geometric normal g and unit interpolated normal n (all on the eye's side): n itself when the mirror
 * image of i about n leaves the surface at least min(0.9 g.i, 0.01) above it, else n turned towards g in
 * their common plane until it does (kernel/closure/bsdf_util.h; Cycles applies it to every closure's
 * normal in svm_node_closure_bsdf, the subsurface closure's included, so its walks enter about it). g
 * where no such normal exists. out may not alias the inputs. */
void valid_reflection_normal(const double g[3], const double i[3], const double n[3], double out[3]);

#endif
