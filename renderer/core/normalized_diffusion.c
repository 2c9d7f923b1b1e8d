/* normalized_diffusion.c - Christensen and Burley's normalized diffusion as a two-source profile: two
 * exponentials over r at the exit point itself, one a third as steep as the other. */
#include "normalized_diffusion.h"
#include "beam_diffusion.h"
#include "linalg.h"
#include "profile.h"

#include <math.h>
#include <string.h>

double burley_scale(double albedo)
{
    double off = fabs(albedo - 0.8);
    return 1.85 - albedo + 7.0 * off * off * off;
}

/* Beam diffusion's albedo takes about 3 ms (a quadrature over radius and depth); a frame needs the same
 * three channels' several times, and a service renders one material many times over. */
static double albedo_of(double sigma_a, double sigma_s_prime, double g, double eta)
{
    enum { ENTRIES = 6 };
    static _Thread_local struct { double key[4], albedo; int used; } cache[ENTRIES];
    static _Thread_local int next;
    const double key[4] = {sigma_a, sigma_s_prime, g, eta};
    for (int i = 0; i < ENTRIES; i++)
        if (cache[i].used && memcmp(cache[i].key, key, sizeof key) == 0)
            return cache[i].albedo;
    /* Diffusion overshoots where nothing absorbs (1.09 at sigma_a = 0, eta 1), where all light that enters
     * must leave again. */
    double albedo = fmin(beam_diffusion_albedo(sigma_a, sigma_s_prime, g, eta), 1.0);
    memcpy(cache[next].key, key, sizeof key);
    cache[next].albedo = albedo;
    cache[next].used = 1;
    next = (next + 1) % ENTRIES;
    return albedo;
}

void burley_profile(struct profile *p, double sigma_a, double sigma_s_prime, double g, double eta)
{
    double albedo = albedo_of(sigma_a, sigma_s_prime, g, eta);
    memset(p, 0, sizeof *p);
    p->kind = LUCENT_PROFILE_BURLEY;
    p->sigma_t_prime = sigma_a + sigma_s_prime;
    /* d = l / s: the steep term's length; the shallow one's is 3 d. */
    double d = 1.0 / (p->sigma_t_prime * burley_scale(albedo));
    p->sigma[0] = 1.0 / d;
    p->sigma[1] = 1.0 / (3.0 * d);
    p->a[0] = p->a[1] = albedo / (8.0 * PI * d);
}
