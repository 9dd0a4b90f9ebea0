/* The planar articulated-body algorithm of aba.c: see there and lib.rs. */
#ifndef KANESTOP_C_ABA_H
#define KANESTOP_C_ABA_H
#include <stddef.h>

typedef struct {
    double mass;        /* kg */
    double inertia;     /* about the centroid, kg m^2 */
    double centroid[2]; /* from the body's joint, body axes (x, z), m */
    double joint[2];    /* the body's joint in the parent's axes (x, z), m; body 0: in the world's at s = 0 */
} aba_body;

/* Doubles of work the caller provides per body. */
#define ABA_WORK_PER_BODY 35

void aba_accelerations(size_t n, const aba_body *bodies, double g, const double *q, const double *u,
                       double *qdd, double *work);

#endif
