/*
 * csv.c - the CSV formats: bodies (one row per body per frame) and
 * statistics (one row per frame).  Numbers in shortest round-trip form;
 * names quoted when they hold a comma, a quote or a line break (RFC 4180),
 * and marked as text when a spreadsheet would read them as a formula.
 */
#include "dump_internal.h"

#include <string.h>

/* Append a name, quoted if needed.  A name a spreadsheet would take for a
 * formula -- one beginning with = + - @, a tab or a carriage return (CSV
 * injection; OWASP, "CSV Injection") -- is written with an apostrophe in
 * front, the spreadsheets' own mark of text, and so is one that begins with
 * an apostrophe: a program reading the file drops one leading apostrophe
 * to get the name back. */
static rbs_status put_name(rbsf__out *out, const char *name)
{
    rbs_status st = RBS_OK;
    const char *c;
    int mark = name[0] != '\0' && strchr("=+-@\t\r'", name[0]) != NULL;
    if (strpbrk(name, ",\"\r\n") == NULL) {
        if (mark)
            st = rbsf__out_put(out, "'", 1);
        return st == RBS_OK ? rbsf__out_put(out, name, strlen(name)) : st;
    }
    st = rbsf__out_put(out, mark ? "\"'" : "\"", mark ? 2 : 1);
    for (c = name; *c && st == RBS_OK; c++)
        st = *c == '"' ? rbsf__out_put(out, "\"\"", 2) : rbsf__out_put(out, c, 1);
    return st == RBS_OK ? rbsf__out_put(out, "\"", 1) : st;
}

/* Append ",x" for each of n numbers. */
static rbs_status put_nums(rbsf__out *out, const double *x, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        rbs_status st = rbsf__out_put(out, ",", 1);
        if (st == RBS_OK)
            st = rbsf__out_num(out, x[i]);
        if (st != RBS_OK)
            return st;
    }
    return RBS_OK;
}

static rbs_status csv_frame(rbsf__out *out, const rbs_frame *f, void *scratch)
{
    uint32_t i;
    rbs_status st = RBS_OK;
    (void)scratch;
    for (i = 0; i < f->body_count && st == RBS_OK; i++) {
        const rbs_frame_body *b = &f->bodies[i];
        st = rbsf__out_uint(out, (unsigned long long)f->number);
        if (st == RBS_OK) st = put_nums(out, &f->time, 1);
        if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
        if (st == RBS_OK) st = rbsf__out_uint(out, b->slot);
        if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
        if (st == RBS_OK) st = put_name(out, b->name ? b->name : "");
        if (st == RBS_OK) st = put_nums(out, b->position, 3);
        if (st == RBS_OK) st = put_nums(out, b->orientation, 4);
        if (st == RBS_OK) st = put_nums(out, b->velocity, 3);
        if (st == RBS_OK) st = put_nums(out, b->angular_velocity, 3);
        if (st == RBS_OK) st = rbsf__out_put(out, "\n", 1);
    }
    return st;
}

static rbs_status stats_frame(rbsf__out *out, const rbs_frame *f, void *scratch)
{
    const rbs_frame_stats *s = &f->stats;
    double e[3];
    rbs_status st;
    (void)scratch;
    e[0] = s->kinetic;
    e[1] = s->potential;
    e[2] = s->total;
    st = rbsf__out_uint(out, (unsigned long long)f->number);
    if (st == RBS_OK) st = put_nums(out, &f->time, 1);
    if (st == RBS_OK) st = put_nums(out, e, 3);
    if (st == RBS_OK) st = put_nums(out, s->momentum, 3);
    if (st == RBS_OK) st = put_nums(out, s->angular_momentum, 3);
    if (st == RBS_OK) st = put_nums(out, &s->step.max_overlap, 1);
    if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
    if (st == RBS_OK) st = rbsf__out_uint(out, s->step.contacts);
    if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
    if (st == RBS_OK) st = rbsf__out_uint(out, s->step.colliding);
    if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
    if (st == RBS_OK) st = rbsf__out_uint(out, s->step.substeps);
    if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
    if (st == RBS_OK) st = rbsf__out_uint(out, s->step.rollbacks);
    if (st == RBS_OK) st = rbsf__out_put(out, ",", 1);
    if (st == RBS_OK) st = rbsf__out_uint(out, s->step.work_limit);
    if (st == RBS_OK) st = rbsf__out_put(out, "\n", 1);
    return st;
}

/* Longest row: 13 numbers of at most 24 characters, a name of at most 63
 * bytes doubled, marked and quoted, two 20-digit integers, commas. */
const rbsf__format rbsf__csv_format = {
    "csv",
    "frame,t,body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n",
    14 * 26 + 2 * RBS_NAME_MAX + 2 + 2 * 21 + 8,
    csv_frame};

const rbsf__format rbsf__stats_format = {
    "stats",
    "frame,t,kinetic,potential,total,px,py,pz,lx,ly,lz,max_overlap,contacts,"
    "collisions,substeps,rollbacks,work_limit\n",
    0, /* one row per frame: fits the 1024 fixed bytes */
    stats_frame};
