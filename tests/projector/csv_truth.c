/*
 * csv_truth.c - a helper for test_cli.py: runs a world with bodies whose
 * names need CSV quoting through the projector with the CSV renderer
 * writing argv[1], and a second renderer printing every frame's exact values
 * with %a (hexadecimal floating point, exact) to standard output, one line
 * per body: frame t body x y z qw qx qy qz vx vy vz wx wy wz.
 * The test reads the CSV with Python's csv module and compares bit for bit.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dump.h"
#include "rbsim/reel.h"

static rbs_status t_create(void *context, const rbs_renderer_config *config,
                           const rbs_world *world, void **instance, char *err,
                           size_t errlen)
{
    (void)context; (void)config; (void)world; (void)err; (void)errlen;
    *instance = stdout;
    return RBS_OK;
}

static void hex(FILE *out, const double *x, int n)
{
    int i;
    for (i = 0; i < n; i++)
        fprintf(out, " %a", x[i]);
}

static rbs_status t_draw(void *instance, const rbs_frame *f, char *err,
                         size_t errlen)
{
    FILE *out = instance;
    uint32_t i;
    (void)err; (void)errlen;
    for (i = 0; i < f->body_count; i++) {
        const rbs_frame_body *b = &f->bodies[i];
        fprintf(out, "%llu %a %u", (unsigned long long)f->number, f->time,
                b->slot);
        hex(out, b->position, 3);
        hex(out, b->orientation, 4);
        hex(out, b->velocity, 3);
        hex(out, b->angular_velocity, 3);
        fputc('\n', out);
    }
    return RBS_OK;
}

static rbs_status t_finish(void *instance, char *err, size_t errlen)
{
    (void)err; (void)errlen;
    return fflush((FILE *)instance) == 0 ? RBS_OK : RBS_E_IO;
}

static void t_destroy(void *instance) { (void)instance; }

int main(int argc, char **argv)
{
    rbs_world_def wd;
    rbs_world *w;
    rbs_plane_def pd;
    rbs_sphere_def sd;
    rbs_body_id id;
    rbs_renderer_registry *reg;
    rbs_renderer_class tc;
    rbs_renderer_config cfg[2];
    rbs_projector_def def;
    rbs_projector *p;
    rbs_status st;
    /* Names with what CSV must mark as text, and characters it must not
     * touch (a name holds no blank, '=', ',' or '"': the scene files' rule,
     * which the API follows); the test knows them by slot. */
    static const char *const names[] = {"+plain", "semi;colon", "single'quote",
                                        "@both'x"};
    int i;

    if (argc != 3) {
        fprintf(stderr, "usage: csv_truth OUT.csv STEPS\n");
        return 2;
    }
    rbs_world_def_init(&wd);
    wd.max_bodies = 8;
    wd.dt = 1.0 / 3.0 * 0.01; /* a step that is not a short decimal */
    if (rbs_world_create(&wd, &w) != RBS_OK)
        return 1;
    rbs_plane_def_init(&pd);
    pd.name = "tilted_floor";
    pd.normal.x = 0.1;
    pd.normal.z = 1;
    rbs_world_add_plane(w, &pd, &id);
    for (i = 0; i < 4; i++) {
        rbs_sphere_def_init(&sd);
        sd.name = names[i];
        sd.radius = 0.1 + 0.01 * i;
        sd.position.x = 0.7 * i;
        sd.position.z = 0.5 + 0.1 * i;
        sd.velocity.x = 0.3 * i - 0.5;
        sd.velocity.y = 1e-7 * i;
        sd.angular_velocity.z = 3.14159 * i;
        if (rbs_world_add_sphere(w, &sd, &id) != RBS_OK) {
            fprintf(stderr, "add sphere '%s': %s\n", names[i],
                    rbs_world_last_error(w));
            return 1;
        }
    }
    memset(&tc, 0, sizeof tc);
    tc.struct_size = sizeof tc;
    tc.name = "truth";
    tc.create = t_create;
    tc.draw = t_draw;
    tc.finish = t_finish;
    tc.destroy = t_destroy;
    rbs_renderer_registry_create(&reg);
    rbs_renderer_register(reg, rbsf_csv_class());
    rbs_renderer_register(reg, &tc);
    memset(cfg, 0, sizeof cfg);
    cfg[0].struct_size = cfg[1].struct_size = sizeof cfg[0];
    cfg[0].type = "csv";
    cfg[0].path = argv[1];
    cfg[1].type = "truth";
    rbs_projector_def_init(&def);
    def.steps = strtoull(argv[2], NULL, 10);
    st = rbs_projector_create(w, reg, cfg, 2, &def, &p);
    if (st == RBS_OK)
        st = rbs_projector_run(p);
    if (st != RBS_OK)
        fprintf(stderr, "csv_truth: %s\n", rbs_projector_last_error(p));
    rbs_projector_destroy(p);
    rbs_renderer_registry_destroy(reg);
    rbs_world_destroy(w);
    return st == RBS_OK ? 0 : 1;
}
