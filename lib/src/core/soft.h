/*
 * soft.h - the soft step's gathered layout (internal): body records,
 * contact chunks and the row kernels that sweep them (soft_rows.h).
 *
 * A frame of the soft step in the gathered layout (step_soft.c) copies each
 * body into a record of RBS__REC doubles, laid out so that four of them
 * load as four lanes in three blocks of four doubles:
 *   block 0: v.x v.y v.z w.x     block 1: w.y w.z d.x d.y
 *   block 2: d.z 1/m 1/I r       block 3: rotation (3), spare
 * (v velocity, w angular velocity, d the displacement since the frame's
 * start, r the radius; 1/m and 1/I are 0 for a fixed sphere and a plane).
 * The contacts are packed in chunks of four lanes whose bodies differ, so a
 * row of each lane runs side by side and the four rows of a chunk give
 * what they would one after the other (soft_chunks.c).  An unused lane
 * reads and writes a record of zeros of the pass's own, so a row there
 * moves nothing.
 */
#ifndef RBS_CORE_SOFT_H
#define RBS_CORE_SOFT_H

#include "core/world_internal.h"

/* The soft contact's spring frequency for sub-steps of h, rad/s: a third
 * of the sub-step rate (why a third: step_soft.c); a load L on a
 * contact of effective mass m sinks it by L / (m omega^2). */
#define RBS__SOFT_HERTZ (1.0 / 3.0)
static inline double rbs__soft_omega(double h)
{
    return 2.0 * 3.14159265358979323846 * RBS__SOFT_HERTZ / h;
}

#define RBS__LANES 4         /* contacts a chunk (core/wide.h: lanes) */
#define RBS__REC 16          /* doubles a body record */
#define RBS__REC_V 0         /* velocity */
#define RBS__REC_W 3         /* angular velocity */
#define RBS__REC_D 6         /* displacement since the frame's start */
#define RBS__REC_IM 9        /* 1/m */
#define RBS__REC_II 10       /* 1/I */
#define RBS__REC_R 11        /* radius (0 for a plane) */
#define RBS__REC_ROT 12      /* rotation since the frame's start, rad */

/* Four contacts side by side (one lane each).  Unused lanes (beyond count)
 * hold zero impulses and row 0; their other fields are left from earlier
 * frames (soft_chunks.c: their rows read a record of zeros). */
typedef struct rbs__chunk {
    uint32_t a[4], b[4];        /* body slots (records; unused lanes: 0) */
    uint32_t row[4];            /* material-pair rows (w->pair: the friction);
                                   unused lanes: a valid row */
    uint32_t count;             /* lanes in use: the first count */
    uint32_t flags;             /* RBS__CH_* bits, 4 a field (bit l: lane l) */
    uint32_t pad[2];
    double nx[4], ny[4], nz[4]; /* unit normal, from b towards a */
    double lb[4];               /* b's lever along n, m (0 for a plane) */
    double gap[4];              /* separation at the frame's start, m */
    double jn[4];               /* accumulated normal impulse, N s */
    double jx[4], jy[4], jz[4]; /* accumulated friction impulse, N s */
    double eb[4];               /* e times the approach speed at the frame's
                                   start (restitution's target), m/s */
} rbs__chunk;
/* The effective masses are not stored: the rows make them from the lanes'
 * records (soft_rows.h, row_chunk), and the friction comes from the pair's
 * row, so a chunk is 384 bytes, six cache lines; the header comes first,
 * because the rows read it first. */
typedef char rbs__chunk_is_384_bytes[sizeof(rbs__chunk) == 384 ? 1 : -1];

#define RBS__CH_TOUCHED 0u  /* took a normal impulse this frame */
#define RBS__CH_BOUNCE 4u   /* restitution takes it (approached faster than
                               its resting threshold at the frame's start) */
#define RBS__CH_GUARD 8u    /* a guard contact (RBS__GUARD) */
#define RBS__CH_PLANE 12u   /* body b is a plane: only a moves */
#define RBS__CH_SERIAL 16u  /* one bit: the lanes may share bodies, and are
                               taken one after the other */
#define RBS__CH_WEDGE 17u   /* one bit, with RBS__CH_SERIAL: lanes 0-1 and
                               2-3 are each a wedge, a sphere's contacts
                               with two planes whose normals are nearly
                               opposed, solved together (soft_rows.h,
                               row_wedge) */
#define RBS__CH_FIXED 18u   /* one bit: some lane's pair has a fixed sphere,
                               whose rows turn (soft_rows.h, row_chunk):
                               the other chunks skip that test */
#define RBS__CH_SLIP 20u    /* it came in slipping more than mu_k times its
                               last frame's normal impulse can stop: only
                               kinetic friction acts this frame
                               (rbs__friction_cap; only where mu_s > mu_k) */
#define RBS__CH_WARM 24u    /* it came in with a normal impulse (the last
                               frame's load) and is not lone: its relax
                               rows over-relax (RBS__SOFT_OVER; the warm
                               start clears it on a lone lane) */

/* The relax rows of a contact that came in loaded take RBS__SOFT_OVER times
 * the rigid row's impulse (successive over-relaxation): one relax pass a
 * sub-step, the only pass that takes energy out of the slow modes of a
 * chain of contacts, reaches those modes less the longer the chain, while
 * the solve's soft rows build their force there only through the
 * accumulated impulse, (1 + a) passes behind; a single column of more than
 * about 21 balls rocked without end (docs/methods.md, "soft", session 45).
 * A new contact (an impact) keeps the rigid row, and the fixed point of a
 * resting load (vn = 0) is the same.  So does a lone contact, whose moving
 * bodies are in no other contact that came in loaded (without
 * RBS__LOADED_MORE in touched, soft_detect.h; a pair apart carries
 * nothing): it is no link of a chain, one rigid row solves it exactly, and
 * over-relaxed it overshoots -- while it sinks into its spring the relax
 * left it rising at half its sink speed, and the next sub-step bore that
 * much less than its load, so a ball at rest on an incline with mu_s
 * within 0.1 % of rolling's need slipped, and with mu_k below it slid for
 * good (docs/methods.md, "soft"; session 50). */
#define RBS__SOFT_OVER 1.5

/* A record's bits in the frame's touched (rbs__soft_in) besides bit 0 (in
 * a contact): in a contact that came in loaded, and in more than one. */
#define RBS__LOADED_ONE 4u
#define RBS__LOADED_MORE 8u /* (twice RBS__LOADED_ONE: soft_detect.c, mark) */

/* A sphere's contacts with two planes are a wedge when their normals' dot
 * product is below this (the planes more than about 154 degrees apart: a
 * groove whose walls are within 13 degrees of parallel).  Their rows alone,
 * one after the other, cannot hold the sphere: the mode in which it sinks
 * into both is 1 / (1 + n1.n2) times heavier than either row's effective
 * mass, each pass moves it by a fraction 1 + n1.n2 of what it needs, and
 * the soft rows' warm-started impulses then follow its depth with a lag,
 * a spring that gains energy (soft_rows.h, row_wedge). */
#define RBS__WEDGE_COS (-0.9)

/* The passes of a frame (step_soft.c). */
enum { RBS__SOFT_SOLVE, RBS__SOFT_RELAX, RBS__SOFT_RESTITUTION, RBS__SOFT_RELAX_REPORT };

/* What a pass reads (the same for every thread of a step). */
typedef struct rbs__soft_rows {
    double *rec;           /* records, RBS__REC doubles a slot */
    rbs__chunk *chunk;     /* the chunks */
    const rbs__pair *pair; /* the material-pair rows (w->pair) */
    int friction;          /* some pair has friction */
    double inv_h;          /* 1 / h, h the sub-step */
    double bias_rate, mass_scale, impulse_scale; /* the soft row's coefficients */
    double slop;           /* def.slop, of the smaller radius */
    double push;           /* SOFT_PUSH / h: the push speed limit per metre of
                              the smaller radius, 1/s */
    double hold;           /* 2 impulse_scale / mass_scale: twice the push
                              speed that holds a contact's load, per m/s of
                              jn / m_eff; the limit is never below it */
    double guard;          /* RBS__GUARD_DEPTH */
    const uint8_t *touched; /* per record: its contacts (rbs__soft_in); the
                               warm start's lone lanes */
    int fixed;             /* some sphere is fixed: a SOLVE or RELAX pass over
                              a group takes the lanes with a fixed sphere
                              touching now first and those apart last
                              (soft_rows.h, pass_stage) */
} rbs__soft_rows;

/* What a pass reports, per share of it (a cache line each). */
typedef struct rbs__soft_report {
    uint32_t touching;     /* RELAX_REPORT: lanes within their slop */
    uint32_t restituted;   /* RESTITUTION: lanes whose impulse it changed */
    double deepest;        /* RELAX_REPORT: the deepest overlap, m (>= 0) */
    unsigned char pad[48];
} rbs__soft_report;

/* The row kernels: one per backend of core/wide.h, the same bits.  Each
 * takes the chunks chunk[begin .. end - 1] in order (stage < 0: the warm start,
 * which applies every lane's accumulated impulses again) and adds what it
 * reports to *report. */
typedef struct rbs__soft_kernels {
    void (*pass)(const rbs__soft_rows *k, int stage, uint32_t begin, uint32_t end, rbs__soft_report *report);
} rbs__soft_kernels;

/* The AVX kernels (soft_rows_avx.c, soft_rows_avx512.c): built by GCC and
 * Clang for x86. */
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
#define RBS_HAVE_AVX_KERNELS 1
#endif

extern const rbs__soft_kernels rbs__soft_kernels_plain;
#if defined(RBS_HAVE_AVX_KERNELS)
extern const rbs__soft_kernels rbs__soft_kernels_avx;    /* AVX */
extern const rbs__soft_kernels rbs__soft_kernels_avx512; /* the AVX source for AVX-512VL */
#endif
/* The kernels of this processor (step_soft.c): the AVX ones for AVX-512VL,
 * else for AVX, where the build has them and the processor runs them, else
 * the plain ones (all the same bits). */
const rbs__soft_kernels *rbs__soft_kernels_best(void);

#endif
