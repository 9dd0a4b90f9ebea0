/*
 * A hand-written planar articulated-body algorithm (Featherstone, "Rigid Body Dynamics
 * Algorithms", 2008, Table 7.1, in the planar spatial algebra of its Section 2.16), for the
 * chain of kanestop's model: body 0 (the anchor) slides along the world x axis on a
 * prismatic joint, bodies 1 .. n-1 (the rods and the ship) hang from revolute joints, and
 * gravity is the only load (as the base's upward acceleration g). Written in the textbook
 * form, generic 3 x 3 products and all, with the C library's sin and cos: the comparator
 * issue 14 names for its weight-alone goal, not a kernel of the tool. See lib.rs.
 *
 * Coordinates: a body's frame has its origin at the body's joint and the body's (x, z) axes
 * as (X, Y). kanestop's rotations about y turn (x, z) by -theta in that plane, so a joint
 * angle here is -beta and the results are negated back.
 */
#include <math.h>
#include "aba.h"

typedef double vec3[3];
typedef double mat3[3][3];

/* Plücker transform from a parent frame to a child frame whose origin is at (rx, ry) in the
 * parent frame and whose axes are turned by phi (c = cos phi, s = sin phi). */
static void transform(double rx, double ry, double c, double s, mat3 x)
{
    x[0][0] = 1.0;
    x[0][1] = 0.0;
    x[0][2] = 0.0;
    x[1][0] = s * rx - c * ry;
    x[1][1] = c;
    x[1][2] = s;
    x[2][0] = c * rx + s * ry;
    x[2][1] = -s;
    x[2][2] = c;
}

static void mat_vec(const mat3 m, const vec3 v, vec3 out)
{
    for (int i = 0; i < 3; i++)
        out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static void mat_t_vec(const mat3 m, const vec3 v, vec3 out)
{
    for (int i = 0; i < 3; i++)
        out[i] = m[0][i] * v[0] + m[1][i] * v[1] + m[2][i] * v[2];
}

/* out += x^T a x: an articulated inertia carried across a joint to the parent. */
static void add_congruence(const mat3 x, const mat3 a, mat3 out)
{
    mat3 ax;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            ax[i][j] = a[i][0] * x[0][j] + a[i][1] * x[1][j] + a[i][2] * x[2][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] += x[0][i] * ax[0][j] + x[1][i] * ax[1][j] + x[2][i] * ax[2][j];
}

/* Motion cross product v x m. */
static void cross_motion(const vec3 v, const vec3 m, vec3 out)
{
    out[0] = 0.0;
    out[1] = -v[0] * m[2] + v[2] * m[0];
    out[2] = v[0] * m[1] - v[1] * m[0];
}

/* Force cross product v x* f. */
static void cross_force(const vec3 v, const vec3 f, vec3 out)
{
    out[0] = v[1] * f[2] - v[2] * f[1];
    out[1] = -v[0] * f[2];
    out[2] = v[0] * f[1];
}

/* Spatial inertia of a body of mass m, inertia about its centroid ic, centroid (cx, cy). */
static void body_inertia(const aba_body *b, mat3 out)
{
    double m = b->mass, cx = b->centroid[0], cy = b->centroid[1];
    out[0][0] = b->inertia + m * (cx * cx + cy * cy);
    out[0][1] = -m * cy;
    out[0][2] = m * cx;
    out[1][0] = -m * cy;
    out[1][1] = m;
    out[1][2] = 0.0;
    out[2][0] = m * cx;
    out[2][1] = 0.0;
    out[2][2] = m;
}

void aba_accelerations(size_t n, const aba_body *bodies, double g, const double *q, const double *u,
                       double *qdd, double *work)
{
    /* Per body, at these offsets of its ABA_WORK_PER_BODY doubles: its transform from the
     * parent 0, velocity 9, velocity product c 12, articulated bias p^A 15 and inertia I^A 18,
     * U = I^A S 27, D^-1 = 1/(S^T U) 30 (one division per body), u = tau - S^T p^A 31 (tau = 0), acceleration 32. */
    for (size_t k = 0; k < n; k++) {
        double *w = work + k * ABA_WORK_PER_BODY;
        double(*x)[3] = (double(*)[3])(w);
        double *v = w + 9, *c = w + 12, *p = w + 15;
        double(*ia)[3] = (double(*)[3])(w + 18);
        const aba_body *b = &bodies[k];
        const double *parent_v = k > 0 ? work + (k - 1) * ABA_WORK_PER_BODY + 9 : NULL;
        if (k == 0) {
            /* The prismatic joint along the world x axis: the anchor's surge s = q[n-1]. */
            transform(b->joint[0] + q[n - 1], b->joint[1], 1.0, 0.0, x);
            v[0] = 0.0;
            v[1] = u[n - 1];
            v[2] = 0.0;
            c[0] = c[1] = c[2] = 0.0; /* the base is at rest */
        } else {
            double phi = -q[k - 1], rate = -u[k - 1];
            transform(b->joint[0], b->joint[1], cos(phi), sin(phi), x);
            mat_vec(x, parent_v, v);
            v[0] += rate;
            vec3 joint_velocity = {rate, 0.0, 0.0};
            cross_motion(v, joint_velocity, c);
        }
        body_inertia(b, ia);
        vec3 momentum;
        mat_vec(ia, v, momentum);
        cross_force(v, momentum, p);
    }

    for (size_t k = n; k-- > 0;) {
        double *w = work + k * ABA_WORK_PER_BODY;
        double(*x)[3] = (double(*)[3])(w);
        double *c = w + 12, *p = w + 15;
        double(*ia)[3] = (double(*)[3])(w + 18);
        double *uu = w + 27, *d_inv = w + 30, *tau = w + 31;
        int axis = k == 0 ? 1 : 0; /* S: the unit motion of the joint */
        for (int i = 0; i < 3; i++)
            uu[i] = ia[i][axis];
        *d_inv = 1.0 / uu[axis];
        *tau = -p[axis];
        if (k == 0)
            break;
        const double dinv = *d_inv;
        mat3 ia_joint;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                ia_joint[i][j] = ia[i][j] - uu[i] * uu[j] * dinv;
        vec3 pa, iac, carried;
        mat_vec(ia_joint, c, iac);
        for (int i = 0; i < 3; i++)
            pa[i] = p[i] + iac[i] + uu[i] * *tau * dinv;
        double *parent = work + (k - 1) * ABA_WORK_PER_BODY;
        add_congruence(x, ia_joint, (double(*)[3])(parent + 18));
        mat_t_vec(x, pa, carried);
        for (int i = 0; i < 3; i++)
            parent[15 + i] += carried[i];
    }

    const vec3 base = {0.0, 0.0, g}; /* gravity as the base's upward acceleration */
    for (size_t k = 0; k < n; k++) {
        double *w = work + k * ABA_WORK_PER_BODY;
        double(*x)[3] = (double(*)[3])(w);
        double *c = w + 12, *uu = w + 27, *d_inv = w + 30, *tau = w + 31, *a = w + 32;
        const double *parent_a = k > 0 ? work + (k - 1) * ABA_WORK_PER_BODY + 32 : base;
        vec3 ap;
        mat_vec(x, parent_a, ap);
        for (int i = 0; i < 3; i++)
            ap[i] += c[i];
        double acc = (*tau - (uu[0] * ap[0] + uu[1] * ap[1] + uu[2] * ap[2])) * *d_inv;
        int axis = k == 0 ? 1 : 0;
        for (int i = 0; i < 3; i++)
            a[i] = ap[i];
        a[axis] += acc;
        if (k == 0)
            qdd[n - 1] = acc;
        else
            qdd[k - 1] = -acc;
    }
}
