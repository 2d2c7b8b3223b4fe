/*
 * test_scene_errors.c - every validation rule has a bad file under bad/
 * (its name says what is wrong) and the exact error text is checked:
 * "file:line:col: path: message".
 *
 * The expected line and column are not taken from the code under test: each
 * case names a marker (a piece of the bad file's text) and an offset into it;
 * the test finds the marker with a plain string search and computes the line
 * and column itself.  The messages are written out in full here.
 */
#include "scene_test.h"

#include <math.h>

typedef struct expect {
    const char *marker; /* text at the error; NULL = end of file */
    int occurrence;     /* 1 = first occurrence of the marker */
    int offset;         /* bytes from the marker's start */
    const char *in;     /* file holding the marker if not the loaded one */
    const char *rest;   /* "path: message" */
} expect;

typedef struct bad_case {
    const char *file;
    rbs_status status;
    expect errors[6];
} bad_case;

#define E(marker, occ, off, rest) {marker, occ, off, NULL, rest}
#define EIN(in, marker, occ, off, rest) {marker, occ, off, in, rest}

static const bad_case cases[] = {
    /* malformed, truncated and odd JSON */
    {"bad/malformed_missing_comma.json", RBS_E_SCENE,
     {E("\"dt\"", 1, 0,
        "simulation: expected ',' or '}' after an object member, got '\"'")}},
    {"bad/truncated.json", RBS_E_SCENE,
     {E(NULL, 1, 0, "bodies[0].radius: expected a value, got end of input (truncated JSON?)")}},
    {"bad/trailing_text.json", RBS_E_SCENE,
     {E("extra", 1, 0, "unexpected 'e' after the end of the JSON value")}},
    {"bad/empty.json", RBS_E_SCENE, {E(NULL, 1, 0, "empty input: expected a JSON object")}},
    {"bad/binary.json", RBS_E_SCENE,
     {E("", 1, 0,
        "expected a value (object, array, string, number, true, false or null), got "
        "byte 0x00")}},
    /* a UTF-16 file was "got byte 0xff" (JSON) or "NUL byte" (text) */
    {"bad/utf16.json", RBS_E_SCENE,
     {E("", 1, 0,
        "the file is UTF-16 (it starts with the byte-order mark FF FE): scene files are "
        "UTF-8; save it as UTF-8")}},
    {"bad/text_utf16/config.txt", RBS_E_SCENE,
     {E("", 1, 0,
        "the file is UTF-16 (it starts with the byte-order mark FE FF): scene files are "
        "UTF-8; save it as UTF-8")}},
    {"bad/too_deep.json", RBS_E_SCENE,
     {E("[[[", 64, 0,
        "description[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
        "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
        "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]: nesting deeper than 64 "
        "levels")}},
    {"bad/bad_escape.json", RBS_E_SCENE,
     {E("\\q", 1, 0, "bodies[0].name: invalid escape in string: \\ followed by 'q'")}},
    {"bad/leading_zero.json", RBS_E_SCENE,
     {E("010", 1, 0, "simulation.steps: invalid number: leading zeros are not allowed")}},
    {"bad/nan_literal.json", RBS_E_SCENE,
     {E("NaN", 1, 0,
        "bodies[0].position[1]: NaN and Infinity are not JSON numbers; numbers must be "
        "finite")}},
    {"bad/infinity_literal.json", RBS_E_SCENE,
     {E("-Infinity", 1, 0,
        "bodies[0].position[2]: NaN and Infinity are not JSON numbers; numbers must be "
        "finite")}},
    {"bad/top_level_array.json", RBS_E_SCENE,
     {E("[1", 1, 0, "a scene must be a JSON object, got an array of 3 elements")}},
    {"bad/format_version_2.json", RBS_E_SCENE,
     {E("2,", 1, 0, "format: must be 1 (this library reads format version 1), got 2")}},
    /* keys */
    {"bad/unknown_key_radus.json", RBS_E_SCENE,
     {E("{\"name\": \"ball\"", 1, 0, "bodies[0]: missing required key \"radius\" (m, > 0)"),
      E("\"radus\"", 1, 0, "bodies[0].radus: unknown key in a sphere (did you mean \"radius\"?)")}},
    {"bad/plane_with_radius.json", RBS_E_SCENE,
     {E("\"radius\": 1}", 1, 0,
        "bodies[1].radius: unknown key in a plane; expected one of: name, type, point, "
        "normal, material, color, texture")}},
    {"bad/duplicate_key.json", RBS_E_SCENE,
     {E("\"mass\"", 2, 0, "bodies[0].mass: duplicate key (first given at line 5, column 55)")}},
    {"bad/missing_steps.json", RBS_E_SCENE,
     {E("{\"dt\"", 1, 0,
        "simulation: missing required key \"steps\" (the number of steps to run, an "
        "integer >= 0)")}},
    {"bad/missing_mass.json", RBS_E_SCENE,
     {E("{\"name\": \"ball\"", 1, 0,
        "bodies[0]: missing required key \"mass\" (kg, > 0; or give \"density\" in "
        "kg/m^3)")}},
    {"bad/mass_and_density.json", RBS_E_SCENE,
     {E("\"density\"", 1, 0, "bodies[0].density: give either \"mass\" or \"density\", not both")}},
    /* types and numbers */
    {"bad/wrong_type_radius_string.json", RBS_E_SCENE,
     {E("\"0.1\"", 1, 0, "bodies[0].radius: must be a number, got \"0.1\"")}},
    {"bad/overflow_1e999.json", RBS_E_SCENE,
     {E("1e999", 1, 0,
        "bodies[0].position[2]: number out of range (overflows a double), got 1e999")}},
    {"bad/underflow_1e-999.json", RBS_E_SCENE,
     {E("1e-999", 1, 0, "bodies[0].mass: number out of range (underflows to 0), got 1e-999")}},
    {"bad/vector_too_short.json", RBS_E_SCENE,
     {E("[0, 1]", 1, 0,
        "bodies[0].position: must be an array of 3 numbers [x, y, z], got an array of 2 "
        "elements")}},
    {"bad/zero_mass.json", RBS_E_SCENE,
     {E("\"mass\": 0", 1, 8, "bodies[0].mass: must be > 0, got 0")}},
    {"bad/negative_radius.json", RBS_E_SCENE,
     {E("-0.1", 1, 0, "bodies[0].radius: must be > 0, got -0.1")}},
    {"bad/zero_dt.json", RBS_E_SCENE, {E("\"dt\": 0", 1, 6, "simulation.dt: must be > 0, got 0")}},
    {"bad/slop_out_of_range.json", RBS_E_SCENE,
     {E("0.1}", 1, 0,
        "simulation.slop: must be in (0, 0.1) (a fraction of the smaller radius), got 0.1")}},
    {"bad/max_sweeps_zero.json", RBS_E_SCENE,
     {E("0}", 1, 0, "simulation.max_sweeps: must be an integer from 1 to 100000, got 0")}},
    {"bad/max_sweeps_fraction.json", RBS_E_SCENE,
     {E("2.5}", 1, 0, "simulation.max_sweeps: must be an integer from 1 to 100000, got 2.5")}},
    {"bad/soft_substeps_zero.json", RBS_E_SCENE,
     {E("0}", 1, 0, "simulation.soft_substeps: must be an integer from 1 to 1000, got 0")}},
    {"bad/soft_substeps_too_large.json", RBS_E_SCENE,
     {E("1001}", 1, 0,
        "simulation.soft_substeps: must be an integer from 1 to 1000, got 1001")}},
    {"bad/soft_substeps_fraction.json", RBS_E_SCENE,
     {E("2.5}", 1, 0, "simulation.soft_substeps: must be an integer from 1 to 1000, got 2.5")}},
    {"bad/soft_tolerance_negative.json", RBS_E_SCENE,
     {E("-0.1}", 1, 0, "simulation.soft_tolerance: must be in [0, 1], got -0.1")}},
    {"bad/soft_tolerance_too_large.json", RBS_E_SCENE,
     {E("2}", 1, 0, "simulation.soft_tolerance: must be in [0, 1], got 2")}},
    {"bad/soft_tolerance_string.json", RBS_E_SCENE,
     {E("\"0.1\"}", 1, 0, "simulation.soft_tolerance: must be a number, got \"0.1\"")}},
    {"bad/slop_not_a_number.json", RBS_E_SCENE,
     {E("\"loose\"", 1, 0, "simulation.slop: must be a number, got \"loose\"")}},
    {"bad/zero_normal.json", RBS_E_SCENE,
     {E("\"normal\": [0, 0, 0]", 1, 10,
        "bodies[1].normal: must be a nonzero vector, got [0, 0, 0]")}},
    {"bad/zero_quaternion.json", RBS_E_SCENE,
     {E("[0, 0, 0, 0]", 1, 0,
        "bodies[0].orientation: must be a nonzero quaternion [w, x, y, z], got [0, 0, 0, "
        "0]")}},
    {"bad/inertia_triangle.json", RBS_E_SCENE,
     {E("[0.001", 1, 0,
        "bodies[0].inertia: principal moments must satisfy the triangle inequality (each "
        "<= the sum of the other two), got [0.001, 0.001, 0.003]")}},
    /* the moments as written: %g showed 2.0000000001 as 2, and the three as
     * if they met the inequality */
    /* each moment finite, their sum (the trace the world takes) not: it
     * read "the moments of inertia (mass 1 kg, radius 0.1 m) underflow or
     * overflow a double" (a probe of session 50) */
    {"bad/inertia_sum_overflow.json", RBS_E_SCENE,
     {E("[6e307", 1, 0,
        "bodies[0].inertia: principal moments must have a finite sum (the world takes the "
        "inertia's trace), got [6e307, 6e307, 6e307]")}},
    /* a body's material "*": it read 'undefined material "*"; materials are
     * the names used in "materials" pairs', which "*" is (session 50) */
    {"bad/body_material_star.json", RBS_E_SCENE,
     {E("\"*\", \"position", 1, 0,
        "bodies[0].material: \"*\" is not a material: it stands for any material in a "
        "\"materials\" pair; give a material named there, or leave \"material\" out for "
        "none")}},
    {"bad/inertia_triangle_narrow.json", RBS_E_SCENE,
     {E("[1, 1", 1, 0,
        "bodies[0].inertia: principal moments must satisfy the triangle inequality (each "
        "<= the sum of the other two), got [1, 1, 2.0000000001]")}},
    /* a fixed sphere never moves: its velocities, force and torque were
     * dropped, silently; zero ones are fine */
    {"bad/fixed_sphere_moving.json", RBS_E_SCENE,
     {E("[1, 0, 0]", 1, 0,
        "bodies[0].velocity: a fixed sphere does not move: must be [0, 0, 0] or left out, "
        "got [1, 0, 0]"),
      E("[5, 0,", 1, 0,
        "bodies[0].angular_velocity: a fixed sphere does not move: must be [0, 0, 0] or "
        "left out, got [5, 0, 0.0000000001]"),
      /* nor did its force or torque do anything: taken silently */
      E("[0, 0, -2]", 1, 0,
        "bodies[0].force: a fixed sphere does not move: must be [0, 0, 0] or left out, "
        "got [0, 0, -2]"),
      E("[0, 1e-300", 1, 0,
        "bodies[0].torque: a fixed sphere does not move: must be [0, 0, 0] or left out, "
        "got [0, 1e-300, 0]")}},
    {"bad/center_of_mass_outside.json", RBS_E_SCENE,
     {E("[0, 0, 0.1]", 1, 0,
        "bodies[0].center_of_mass: must lie inside the sphere: |offset| = 0.1 m, radius "
        "0.1 m")}},
    {"bad/restitution_above_1.json", RBS_E_SCENE,
     {E("1.5", 1, 0, "simulation.restitution: must be in [0, 1], got 1.5")}},
    {"bad/pair_restitution_negative.json", RBS_E_SCENE,
     {E("-0.2", 1, 0, "materials[0].restitution: must be in [0, 1], got -0.2")}},
    {"bad/negative_friction.json", RBS_E_SCENE,
     {E("-0.3", 1, 0, "materials[0].kinetic: must be >= 0, got -0.3")}},
    {"bad/kinetic_above_static.json", RBS_E_SCENE,
     {E("0.7", 1, 0,
        "materials[0].kinetic: must not exceed the static friction (0.5), got 0.7")}},
    {"bad/kinetic_above_static_narrow.json", RBS_E_SCENE,
     {E("0.50000000002", 1, 0,
        "materials[0].kinetic: must not exceed the static friction (0.50000000001), got "
        "0.50000000002")}},
    {"bad/steps_fraction.json", RBS_E_SCENE,
     {E("10.5", 1, 0,
        "simulation.steps: must be a non-negative integer (at most 2^53), got 10.5")}},
    {"bad/steps_negative.json", RBS_E_SCENE,
     {E("-1", 1, 0, "simulation.steps: must be a non-negative integer (at most 2^53), got -1")}},
    {"bad/steps_too_large.json", RBS_E_SCENE,
     {E("18446744073709551616", 1, 0,
        "simulation.steps: must be a non-negative integer (at most 2^53), got "
        "18446744073709551616")}},
    {"bad/invalid_utf8_name.json", RBS_E_SCENE,
     {E("\xff", 1, 0, "bodies[0].name: invalid UTF-8 in a string (byte 0xff)")}},
    /* the world's own limits, named at the key */
    {"bad/limits_simulation.json", RBS_E_SCENE,
     {E("9007199254740993", 1, 0,
        "simulation.steps: must be a non-negative integer (at most 2^53), got "
        "9007199254740993 (a double cannot hold it exactly: integers above 2^53 are "
        "rounded)"),
      E("1e-20", 1, 0, "simulation.tolerance: must be >= 1e-15 (double precision), got 1e-20"),
      E("\"out/a.csv\"", 2, 0,
        "renderers[1].path: renderers[0] already writes \"out/a.csv\"; give each renderer "
        "its own path")}},
    /* two spellings of one path as written (the command line caught these
     * without a place) */
    {"bad/renderer_paths_one_file.json", RBS_E_SCENE,
     {E("\"./out//a.csv\"", 1, 0,
        "renderers[1].path: renderers[0] already writes \"out/a.csv\", the file "
        "\"./out//a.csv\" names; give each renderer its own path"),
      E("\"/tmp/./frames/\"", 1, 0,
        "renderers[3].path: renderers[2] already writes \"/tmp/frames\", the file "
        "\"/tmp/./frames/\" names; give each renderer its own path")}},
    {"bad/limits_bodies.json", RBS_E_SCENE,
     {E("1, \"position\": [0", 1, 0,
        "bodies[0].mass: the moments of inertia (mass 1 kg, radius 1e-300 m) underflow or "
        "overflow a double: the inertia and its inverse must be finite and nonzero"),
      E("1e-308", 1, 0,
        "bodies[1].mass: the moments of inertia (mass 1e-308 kg, radius 0.1 m) underflow "
        "or overflow a double: the inertia and its inverse must be finite and nonzero"),
      E("[0.0999999", 1, 0,
        "bodies[2].center_of_mass: |offset| = 0.0999999 m is too far from the centre for "
        "this inertia (the inertia about the centre of mass would not be positive "
        "definite)"),
      E("[3, 0, 1.1]", 1, 0,
        "bodies[3].position: the potential energy in gravity at the start is inf J, beyond "
        "1e300 J (the world's energy would overflow)")}},
    /* the momentum and angular momentum about the origin at the start too:
     * a sphere at 1e300 m moving at 1e100 m/s passed the check and failed
     * the first frame ("momentum: numerical failure") */
    {"bad/momentum_overflow.json", RBS_E_SCENE,
     {E("[1e100", 1, 0,
        "bodies[0].velocity: the angular momentum r x m v about the origin (position and "
        "velocity) at the start is inf kg m^2/s, beyond 1e300 kg m^2/s (the world's angular "
        "momentum would overflow)"),
      E("[0.001", 1, 0,
        "bodies[1].velocity: the momentum m v at the start is 1e+302 kg m/s, beyond 1e300 "
        "kg m/s (the world's momentum would overflow)")}},
    /* with mutual gravity, each pair's potential at the start too (a pair of
     * fixed spheres, c and d, is left out, as the world's energy leaves it) */
    {"bad/mutual_gravity_potential_overflow.json", RBS_E_SCENE,
     {E("[1, 0, 0]", 1, 0,
        "bodies[1].position: the potential energy of mutual gravity of \"b\" and \"a\" "
        "(bodies[0]) at the start is 1e+308 J, beyond 1e300 J (the world's energy would "
        "overflow; softening bounds it)"),
      E("[20, 0, 0]", 1, 0,
        "bodies[2].position: the potential energy of mutual gravity of \"c\" and \"a\" "
        "(bodies[0]) at the start is 5e+306 J, beyond 1e300 J (the world's energy would "
        "overflow; softening bounds it)"),
      E("[21, 0, 0]", 1, 0,
        "bodies[3].position: the potential energy of mutual gravity of \"d\" and \"a\" "
        "(bodies[0]) at the start is 4.7619e+306 J, beyond 1e300 J (the world's energy would "
        "overflow; softening bounds it)")}},
    {"bad/steps_dt_overflow.json", RBS_E_SCENE,
     {E("9007199254740992", 1, 0,
        "simulation.steps: steps * dt overflows (9007199254740992 * 1e+300 s)")}},
    /* names and choices */
    {"bad/unknown_method.json", RBS_E_SCENE,
     {E("\"rk45\"", 1, 0,
        "simulation.method: must be \"euler\", \"selective\", \"event\", \"verlet\", "
        "\"rk4\", \"adaptive\", \"soft\" or \"auto\", got \"rk45\" (did you mean \"rk4\"?)")}},
    {"bad/unknown_gravity_mode.json", RBS_E_SCENE,
     {E("\"accel\"", 1, 0,
        "simulation.gravity_mode: must be \"acceleration\" or \"force\", got \"accel\" "
        "(did you mean \"acceleration\"?)")}},
    {"bad/unknown_texture.json", RBS_E_SCENE,
     {E("\"chequer\"", 1, 0,
        "bodies[1].texture: must be \"none\", \"stripes\" or \"checker\", got "
        "\"chequer\" (did you mean \"checker\"?)")}},
    {"bad/bad_color.json", RBS_E_SCENE,
     {E("\"#12345g\"", 1, 0,
        "bodies[0].color: must be \"#rrggbb\" or three numbers in [0, 1] (red, green, "
        "blue), got \"#12345g\"")}},
    {"bad/color_component_above_1.json", RBS_E_SCENE,
     {E("[1, 0.5, 2]", 1, 9, "bodies[0].color[2]: must be in [0, 1], got 2")}},
    {"bad/name_with_space.json", RBS_E_SCENE,
     {E("\"my ball\"", 1, 0,
        "bodies[0].name: a name must not contain spaces, control characters, '#', '\"', "
        "'=' or ',', got \"my ball\"")}},
    /* (the value echoed as JSON writes it: its quote and backslash escaped) */
    {"bad/name_with_quote.json", RBS_E_SCENE,
     {E("\"\\\"q\\\\\"", 1, 0,
        "bodies[0].name: a name must not contain spaces, control characters, '#', '\"', "
        "'=' or ',', got \"\\\"q\\\\\"")}},
    {"bad/duplicate_body_name.json", RBS_E_SCENE,
     {E("\"ball\"", 2, 0,
        "bodies[1].name: duplicate body name \"ball\" (first used by bodies[0])")}},
    {"bad/undefined_material.json", RBS_E_SCENE,
     {E("\"rubbr\"", 1, 0,
        "bodies[0].material: undefined material \"rubbr\" (did you mean \"rubber\"?)")}},
    {"bad/missing_material_pair.json", RBS_E_SCENE,
     {E("\"material\": \"concrete\"", 1, 12,
        "bodies[1].material: no material pair for [\"rubber\", \"concrete\"]: bodies "
        "\"ball\" and \"floor\" could touch; add the pair or a \"*\" row to "
        "\"materials\"")}},
    /* bodies at the start */
    {"bad/overlap_spheres.json", RBS_E_SCENE,
     {E("[0, 0.15, 1]", 1, 0,
        "bodies[1].position: \"ball2\" overlaps \"ball\" (bodies[0]) by 0.05 m at the "
        "start")}},
    {"bad/sphere_behind_plane.json", RBS_E_SCENE,
     {E("[0, 0, 0.05]", 1, 0,
        "bodies[0].position: \"ball\" starts behind (inside) plane \"floor\" (bodies[1]) "
        "by 0.05 m at the start")}},
    /* renderers */
    {"bad/too_many_renderers.json", RBS_E_SCENE,
     {E("{\"type\": \"csv\", \"path\": \"out/4.csv\"}", 1, 0,
        "renderers[4]: at most 4 renderers may be attached, this is number 5")}},
    {"bad/renderer_every_zero.json", RBS_E_SCENE,
     {E("0}", 1, 0, "renderers[0].every: must be an integer from 1 to 2147483647 (2^31 - 1), got 0")}},
    {"bad/renderer_missing_type.json", RBS_E_SCENE,
     {E("{\"path\"", 1, 0,
        "renderers[0]: missing required key \"type\" (the renderer type, e.g. \"csv\", "
        "\"json\" or \"sdl\")")}},
    {"bad/renderer_csv_unknown_key.json", RBS_E_SCENE,
     {E("\"evrey\"", 1, 0, "renderers[0].evrey: unknown key in csv (did you mean \"every\"?)")}},
    /* a type the library does not know: a key given twice at any depth */
    {"bad/renderer_duplicate_nested.json", RBS_E_SCENE,
     {E("\"b\": 2", 1, 0, "renderers[0].a.b: duplicate key (first given at line 4, column 40)"),
      E("\"d\": 2", 1, 0,
        "renderers[0].l[1].c.d: duplicate key (first given at line 4, column 80)")}},
    /* and an integer a double would round (convert wrote 9007199254740992) */
    {"bad/renderer_integer_above_2_53.json", RBS_E_SCENE,
     {E("9007199254740993", 1, 0,
        "renderers[0].id: the integer 9007199254740993 is beyond 2^53, which a double cannot "
        "hold exactly (it would be read as 9007199254740992); give it as a string"),
      E("-1234", 1, 0,
        "renderers[0].l[1]: the integer -123456789012345678901234 is beyond 2^53, which a "
        "double cannot hold exactly (it would be read as -123456789012345685803008); give it "
        "as a string")}},
    {"bad/text_renderer_duplicate/config.txt", RBS_E_SCENE,
     {E("a.b=2", 1, 0, "renderers[0].a.b: duplicate key (first given at line 3, column 17)")}},
    /* stats knows the keys csv and json know (the command refused others
     * at the entry's '{', with no suggestion) */
    {"bad/renderer_stats_unknown_key.json", RBS_E_SCENE,
     {E("\"evrey\"", 1, 0, "renderers[0].evrey: unknown key in stats (did you mean \"every\"?)"),
      E("\"foo\"", 1, 0,
        "renderers[0].foo: unknown key in stats; expected one of: type, path, every")}},
    {"bad/renderer_sdl_bad_width.json", RBS_E_SCENE,
     {E("8}", 1, 0, "renderers[0].width: must be an integer in 16..8192 (pixels), got 8")}},
    {"bad/camera_up_parallel.json", RBS_E_SCENE,
     {E("\"up\": [", 1, 6,
        "renderers[0].camera.up: must be nonzero and not parallel to the view direction "
        "(target - position = [0, 0, -5]), got [0, 0, 1]")}},
    {"bad/camera_target_equals_position.json", RBS_E_SCENE,
     {E("\"target\": [", 1, 10,
        "renderers[0].camera.target: must differ from the position, got [1, 2, 3] for both")}},
    {"bad/camera_bad_fov_and_far.json", RBS_E_SCENE,
     {E("180", 1, 0, "renderers[0].camera.fov: must be in [1e-6, 180) degrees, got 180"),
      E("0.5}", 1, 0, "renderers[0].camera.far: must be > near (1), got 0.5")}},
    /* camera values the renderer cannot use: rejected here, not mid-run */
    {"bad/camera_fov_underflow.json", RBS_E_SCENE,
     {E("1e-300", 1, 0, "renderers[0].camera.fov: must be in [1e-6, 180) degrees, got 1e-300")}},
    {"bad/camera_position_overflow.json", RBS_E_SCENE,
     {E("[1e300", 1, 0,
        "renderers[0].camera.position: coordinates must be within +-1e100 m, got [1e300, 0, 0]")}},
    {"bad/camera_offset_overflow.json", RBS_E_SCENE,
     {E("[1e300", 1, 0,
        "renderers[0].camera.offset: coordinates must be within +-1e100 m, got [1e300, 0, 0]")}},
    {"bad/camera_offset_underflow.json", RBS_E_SCENE,
     {E("[0, 1e-300", 1, 0,
        "renderers[0].camera.offset: must be at least 1e-100 m long (too close to the body to "
        "aim), got [0, 1e-300, 0]")}},
    {"bad/camera_path_overflow.json", RBS_E_SCENE,
     {E("[0, 0, -1e200]", 1, 0,
        "renderers[0].camera.path[0].target: coordinates must be within +-1e100 m, got [0, 0, "
        "-1e200]")}},
    {"bad/renderer_sdl_too_many_pixels.json", RBS_E_SCENE,
     {E("8192}", 1, 0,
        "renderers[0].height: 8192 x 8192 pixels is too large (at most 16 Mpixel = 16777216 per "
        "view)")}},
    {"bad/camera_mount_unknown.json", RBS_E_SCENE,
     {E("\"bal\"", 1, 0,
        "renderers[0].camera.mount: no sphere named \"bal\" (did you mean \"ball\"?)")}},
    /* position and target of a mounted camera were refused only by the sdl
     * renderer's check, at the renderer entry (a probe of session 46) */
    {"bad/camera_mounted_position.json", RBS_E_SCENE,
     {E("\"position\": [1", 1, 0,
        "renderers[0].views[0].position: not used by a mounted camera (it looks at the body "
        "from \"offset\")"),
      E("\"target\"", 1, 0,
        "renderers[0].views[1].target: not used by a mounted camera (it looks at the body "
        "from \"offset\")")}},
    /* a path through its target between keyframes passed, and the sdl
     * renderer stopped the run at the frame where they met (a probe of
     * session 46); one that passes 0.5 mm beside it is fine */
    {"bad/camera_path_through_target.json", RBS_E_SCENE,
     {E("\"target\": [1, 0.001, 1]", 1, 10,
        "renderers[0].camera.path[2].target: between keyframes 1 and 2 the position passes "
        "through the target (at t = 2 s, where the camera would have no view); add a "
        "keyframe that goes around it")}},
    {"bad/camera_and_views.json", RBS_E_SCENE,
     {E("\"views\"", 1, 0, "renderers[0].views: give either \"camera\" or \"views\", not both")}},
    {"bad/camera_path_time_decreasing.json", RBS_E_SCENE,
     {E("\"t\": 0.5", 1, 5, "renderers[0].camera.path[1].t: times must increase, got 0.5 after 1")}},
    {"bad/views_too_many.json", RBS_E_SCENE,
     {E("[{}, {}", 1, 0, "renderers[0].views: must have 1 to 4 cameras, got 5")}},
    /* the "event" method's scope, which its step checks, is decided at load
     * as far as the scene decides it: mutual gravity, a resistance row that
     * a moving sphere's material takes (not steel on steel: the fixed
     * sphere alone is steel), a moving sphere with anisotropic inertia or
     * an off-centre mass (not the fixed one, nor the isotropic "d") */
    {"bad/event_out_of_scope.json", RBS_E_SCENE,
     {E("{\"G\"", 1, 0,
        "simulation.mutual_gravity: method \"event\" does not support mutual gravity (not a "
        "constant force); use \"adaptive\""),
      E("0.001}", 1, 0,
        "materials[0].spinning: method \"event\" does not support rolling and spinning "
        "resistance (pair \"rubber\"/\"*\", which bodies of this scene take); use \"euler\""),
      E("[0.004", 1, 0,
        "bodies[0].inertia: method \"event\" does not support a moving sphere with anisotropic "
        "inertia (\"a\"); use \"euler\""),
      E("[0.01, 0, 0]", 1, 0,
        "bodies[1].center_of_mass: method \"event\" does not support a moving sphere with an "
        "off-centre mass (\"b\"); use \"euler\"")}},
    /* several errors in one file: all are reported, sorted by place (a
     * missing key is reported at its object's opening brace) */
    {"bad/many_errors.json", RBS_E_SCENE,
     {E("-1", 1, 0, "simulation.dt: must be > 0, got -1"),
      E("{\"name\": \"ball\"", 1, 0,
        "bodies[0]: missing required key \"mass\" (kg, > 0; or give \"density\" in "
        "kg/m^3)"),
      E("\"radius\": 0", 1, 10, "bodies[0].radius: must be > 0, got 0"),
      E("\"mas\"", 1, 0, "bodies[0].mas: unknown key in a sphere (did you mean \"mass\"?)"),
      E("\"red\"", 1, 0,
        "bodies[1].color: must be \"#rrggbb\" or three numbers in [0, 1] (red, green, "
        "blue), got \"red\"")}},
    /* the text format: same rules, places in the file that holds the value */
    {"bad/text_unknown_key/config.txt", RBS_E_SCENE,
     {EIN("bad/text_unknown_key/objects.txt", "sphere", 1, 0,
          "bodies[0]: missing required key \"radius\" (m, > 0)"),
      EIN("bad/text_unknown_key/objects.txt", "radus", 1, 0,
          "bodies[0].radus: unknown key in a sphere (did you mean \"radius\"?)")}},
    /* comma lists: an empty element was dropped ("0,,0, -9.81" a 3-vector),
     * and "list=1,b" was [1, "b"] */
    {"bad/text_comma_lists/config.txt", RBS_E_SCENE,
     {E(",,0, -9.81", 1, 1,
        "element 2 of a comma list is empty (nothing between two commas): give its value "
        "or remove the comma"),
      E(",2,3", 1, 0,
        "element 2 of a comma list is empty (nothing between two commas): give its value "
        "or remove the comma"),
      E(",0,0", 1, 0,
        "element 1 of a comma list is empty (a comma before the first value): give its "
        "value or remove the comma"),
      E("b\n", 1, 0,
        "\"b\" in \"list=1,b\" is not a number: a value with commas is an array of "
        "numbers (give other values by index, list[1]=...)")}},
    /* a decimal comma ("0,001", German settings) is a list of two: said
     * so (it was only "got an array of 2 elements"); "001" is no number of
     * its own */
    {"bad/text_decimal_comma/config.txt", RBS_E_SCENE,
     {E("0,001", 1, 0,
        "simulation.dt: must be a number, got an array of 2 elements (a decimal "
        "comma? write the number with a point, e.g. 0.5: a comma separates values)"),
      EIN("bad/text_decimal_comma/objects.txt", "0,1", 1, 0,
          "bodies[0].radius: must be a number, got an array of 2 elements (a decimal "
          "comma? write the number with a point, e.g. 0.5: a comma separates values)"),
      EIN("bad/text_decimal_comma/objects.txt", "0,5", 1, 0,
          "bodies[0].position: must be an array of 3 numbers [x, y, z], got an array "
          "of 4 elements (a decimal comma? write the number with a point, e.g. 0.5: a "
          "comma separates values)")}},
    {"bad/text_bad_material_row/config.txt", RBS_E_SCENE,
     {EIN("bad/text_bad_material_row/materials.txt", "rubber rubber", 1, 0,
          "expected 4 to 7 columns: material_a material_b static kinetic [restitution "
          "[rolling [spinning]]], got 3")}},
    /* a byte-order mark is skipped (line 1 is fine); a bad escape, invalid
     * UTF-8 (the file stops there) and a mistyped body line are errors */
    {"bad/text_mistakes/config.txt", RBS_E_SCENE,
     {E("\\q", 1, 0,
        "invalid escape \\q in a quoted string; the escapes are \\\" \\\\ \\n \\t \\r"),
      EIN("bad/text_mistakes/materials.txt", "\xe9", 1, 0,
          "invalid UTF-8 (byte 0xe9): scene files are UTF-8"),
      EIN("bad/text_mistakes/objects.txt", "cube", 1, 0,
          "unknown body type \"cube\"; a body starts with \"sphere NAME\" or \"plane "
          "NAME\"")}},
    /* a config key with the JSON's prefix is said to be one (it was
     * "simulation.simulation.steps: unknown key"); a '#' word that is no
     * colour after "color" is said to be a malformed colour (it was "missing
     * value after "color""), while a '#' and a blank still begin a comment */
    {"bad/text_prefix_and_colour/config.txt", RBS_E_SCENE,
     {E("# the", 1, 0,
        "simulation: missing required key \"steps\" (the number of steps to run, an integer "
        ">= 0)"),
      E("simulation.steps", 1, 0,
        "simulation.steps: config.txt's keys have no \"simulation.\" prefix: write \"steps = "
        "...\""),
      EIN("bad/text_prefix_and_colour/objects.txt", "#d0303 ", 1, 0,
          "bodies[0].color: must be \"#rrggbb\" or three numbers in [0, 1], got \"#d0303\": not "
          "'#' and 6 hex digits, so it was read as a comment"),
      EIN("bad/text_prefix_and_colour/objects.txt", "color # a", 1, 0,
          "missing value after \"color\"")}},
    {"bad/text_no_block/config.txt", RBS_E_SCENE,
     {EIN("bad/text_no_block/objects.txt", "radius", 1, 0,
          "expected \"sphere NAME\" or \"plane NAME\" to start a body, got \"radius\"")}},
    {"bad/text_deep_key/config.txt", RBS_E_SCENE,
     {E("a[0]", 1, 0, "key nests deeper than 64 levels")}},
    {"bad/text_missing_objects_file/config.txt", RBS_E_IO,
     {E("nothere.txt", 1, 0,
        "cannot open 'bad/text_missing_objects_file/nothere.txt': No such file or "
        "directory")}},
    /* a renderer line's bad keys: each is reported at its place (only the
     * first was, the rest of the line unread), and a bad key leaves nothing
     * behind: "camera..x" made no "camera" for csv to call unknown */
    {"bad/text_renderer_keys/config.txt", RBS_E_SCENE,
     {E("..b", 1, 1, "bad key \"a..b\": expected names joined by '.' and [index]"),
      E("[]", 1, 1, "bad index in key \"a[]\": expected [number]"),
      E("[0=", 1, 1, "bad index in key \"a[0\": expected [number]")}},
    {"bad/text_renderer_words/config.txt", RBS_E_SCENE,
     {E("word", 1, 0, "expected key=value, got \"word\""),
      E("..x", 1, 1, "bad key \"camera..x\": expected names joined by '.' and [index]"),
      E(" x=", 1, 1, "missing value after \"x=\""),
      E("every=0", 1, 6,
        "renderers[0].every: must be an integer from 1 to 2147483647 (2^31 - 1), got 0")}},
    /* messages that misled: a key missing before '=' (it was "simulation.:
     * unknown key"), a word after a file name ("expected a file name"), an
     * array or object given keys or [index] (it was "was given a value"), a
     * number literal over 63 characters (it was "must be a number") */
    {"bad/text_misleading/config.txt", RBS_E_SCENE,
     {E("= 5", 1, 0, "missing key before '=': expected \"key = value\""),
      E("extra", 1, 0,
        "extra word \"extra\" after the file name of \"objects\" (one name; quote a name "
        "with blanks or commas: objects = \"my file.txt\")"),
      E("a.b=2", 1, 0, "\"a\" is an array (given by [index]) and cannot also have keys"),
      E("c[0]=2", 1, 0, "\"c\" is an object (given by keys) and cannot also have [index]"),
      E("e.f=2", 1, 0, "\"e\" was given a value and cannot also have keys"),
      EIN("bad/text_misleading/objects.txt", "0.111", 1, 0,
          "number literal longer than 63 characters (72)")}},
    /* carriage returns alone (old Mac line endings): said so, once (it was
     * one long line: "missing objects", steps "an array of 7 elements") */
    {"bad/text_cr_only/config.txt", RBS_E_SCENE,
     {E("\robjects", 1, 0,
        "a carriage return (\\r) not followed by a line feed: lines end in \\n or \\r\\n (a "
        "file with carriage returns alone, old Mac line endings, reads as one line; convert "
        "it, e.g. tr '\\r' '\\n')")}},
    /* ... also as the file's last byte (it passed; a probe of session 45) */
    {"bad/text_cr_at_end/config.txt", RBS_E_SCENE,
     {E("\r", 1, 0,
        "a carriage return (\\r) not followed by a line feed: lines end in \\n or \\r\\n (a "
        "file with carriage returns alone, old Mac line endings, reads as one line; convert "
        "it, e.g. tr '\\r' '\\n')")}},
    {"bad/text_bad_values/config.txt", RBS_E_SCENE,
     {E("abc", 1, 0,
        "simulation.steps: must be a non-negative integer (at most 2^53), got \"abc\""),
      E("1e999", 1, 0, "simulation.dt: number out of range (overflows a double), got 1e999"),
      E("0 0", 1, 0,
        "simulation.gravity: must be an array of 3 numbers [x, y, z], got an array of 2 "
        "elements"),
      E("-1", 1, 0, "simulation.mutual_gravity.G: must be > 0, got -1"),
      E("every=0", 1, 6, "renderers[0].every: must be an integer from 1 to 2147483647 (2^31 - 1), got 0"),
      EIN("bad/text_bad_values/objects.txt", "nan", 1, 0,
          "bodies[0].position[2]: must be a number, got \"nan\"")}},
};

#define CASE_COUNT (sizeof cases / sizeof *cases)

/* The exact text expected for one error. */
static void expected_text(const bad_case *c, const expect *x, char *out, size_t n)
{
    const char *in = x->in != NULL ? x->in : c->file;
    size_t len = 0, off;
    char *text = read_all(in, &len);
    int line, col;
    assert_non_null(text);
    if (x->marker == NULL) {
        off = len;
    } else if (x->marker[0] == '\0') {
        off = 0;
    } else {
        const char *p = text;
        int k;
        for (k = 0; k < x->occurrence; k++) {
            p = strstr(k == 0 ? p : p + 1, x->marker);
            if (p == NULL) {
                fail_msg("marker '%s' (#%d) not in %s", x->marker, x->occurrence, in);
            }
        }
        off = (size_t)(p - text) + (size_t)x->offset;
    }
    line_col(text, off, &line, &col);
    free(text);
    snprintf(out, n, "%s:%d:%d: %s", in, line, col, x->rest);
}

static void test_bad_files(void **state)
{
    size_t i;
    int failures = 0;
    (void)state;
    for (i = 0; i < CASE_COUNT; i++) {
        const bad_case *c = &cases[i];
        rbs_scene *scene = NULL;
        rbs_status st = rbs_scene_load(c->file, RBS_SCENE_AUTO, &scene);
        uint32_t k, want = 0;
        int ok = 1;
        while (want < 6 && c->errors[want].rest != NULL) {
            want++;
        }
        if (st != c->status || scene == NULL || rbs_scene_error_count(scene) != want) {
            ok = 0;
        }
        for (k = 0; ok && k < want; k++) {
            char expected[1024];
            rbs_scene_error e;
            expected_text(c, &c->errors[k], expected, sizeof expected);
            if (rbs_scene_error_get(scene, k, &e) != RBS_OK || strcmp(e.text, expected) != 0) {
                fprintf(stderr, "%s: error %u\n  expected: %s\n  got:      %s\n", c->file, k,
                        expected, rbs_scene_error_get(scene, k, &e) == RBS_OK ? e.text : "-");
                ok = 0;
            }
        }
        if (!ok) {
            fprintf(stderr, "FAIL %s: status %s (want %s), %u errors (want %u):\n", c->file,
                    rbs_status_name(st), rbs_status_name(c->status),
                    rbs_scene_error_count(scene), want);
            print_errors(scene);
            failures++;
        } else {
            /* nothing runs: a rejected scene builds no world */
            rbs_world *world = NULL;
            rbs_world_def def;
            if (rbs_scene_build(scene, &world) != RBS_E_SCENE || world != NULL ||
                rbs_scene_world_def(scene, &def) != RBS_E_SCENE) {
                fprintf(stderr, "FAIL %s: a rejected scene built a world\n", c->file);
                failures++;
            }
            rbs_world_destroy(world);
        }
        rbs_scene_free(scene);
    }
    assert_int_equal(failures, 0);
}

/* The parts of an error are consistent with its text. */
static void test_error_fields(void **state)
{
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_int_equal(rbs_scene_load("bad/negative_radius.json", RBS_SCENE_JSON, &scene),
                     RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.file, "bad/negative_radius.json");
    assert_string_equal(e.path, "bodies[0].radius");
    assert_string_equal(e.message, "must be > 0, got -0.1");
    /* line 5, column 50: counted by hand in the file */
    assert_int_equal(e.line, 5);
    assert_int_equal(e.column, 50);
    assert_string_equal(e.text, "bad/negative_radius.json:5:50: bodies[0].radius: must be > 0, got -0.1");
    assert_int_equal(rbs_scene_error_get(scene, 1, &e), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_scene_error_get(NULL, 0, &e), RBS_E_INVALID);
    rbs_scene_free(scene);
}

/* Unreadable files: missing, a folder, and a folder without config.txt. */
static void test_unreadable(void **state)
{
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_int_equal(rbs_scene_load("bad/no_such_file.json", RBS_SCENE_AUTO, &scene), RBS_E_IO);
    assert_non_null(scene);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "bad/no_such_file.json: cannot open 'bad/no_such_file.json': "
                                "No such file or directory");
    rbs_scene_free(scene);

    assert_int_equal(rbs_scene_load("bad", RBS_SCENE_JSON, &scene), RBS_E_IO);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "bad: cannot read 'bad': is a directory");
    rbs_scene_free(scene);

    /* a folder stands for its config.txt */
    assert_int_equal(rbs_scene_load("bad", RBS_SCENE_AUTO, &scene), RBS_E_IO);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "bad/config.txt: cannot open 'bad/config.txt': No such file "
                                "or directory");
    rbs_scene_free(scene);

    /* a JSON file with another name is recognised by its first '{' */
    assert_int_equal(rbs_scene_load("bad/json_named.txt", RBS_SCENE_AUTO, &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "bad/json_named.txt:3:47: bodies[0].radius: must be > 0, got 0");
    rbs_scene_free(scene);

    assert_int_equal(rbs_scene_load(NULL, RBS_SCENE_AUTO, &scene), RBS_E_INVALID);
    assert_null(scene);
    assert_int_equal(rbs_scene_load("x.json", RBS_SCENE_AUTO, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_scene_load("x.json", (rbs_scene_format)7, &scene), RBS_E_INVALID);
}

/* More errors than RBS_SCENE_ERRORS_MAX: all are counted, the first kept. */
static void test_error_limit(void **state)
{
    char *text = malloc(200000);
    size_t n = 0;
    int i;
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_non_null(text);
    n += (size_t)sprintf(text + n, "{\"simulation\": {\"steps\": 1},\n\"bodies\": [\n");
    for (i = 0; i < 60; i++) {
        n += (size_t)sprintf(text + n,
                             "%s{\"name\": \"b%d\", \"type\": \"sphere\", \"radius\": -1, "
                             "\"mass\": 1, \"position\": [%d, 0, 0]}\n",
                             i ? "," : "", i, 10 * i);
    }
    n += (size_t)sprintf(text + n, "]}\n");
    assert_int_equal(rbs_scene_parse_json(text, n, "many", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 60);
    assert_int_equal(rbs_scene_error_get(scene, RBS_SCENE_ERRORS_MAX - 1, &e), RBS_OK);
    /* the 50th body (bodies[49]) is on line 52: ",{\"name\": \"b49\", \"type\":
     * \"sphere\", \"radius\": -1": the value starts at column 46 */
    assert_string_equal(e.text, "many:52:46: bodies[49].radius: must be > 0, got -1");
    assert_int_equal(rbs_scene_error_get(scene, RBS_SCENE_ERRORS_MAX, &e), RBS_E_NOT_FOUND);
    rbs_scene_free(scene);
    free(text);
}

/* A camera path of more than 100000 keyframes is refused by the scene at
 * the path (it passed, and the sdl renderer refused it at the entry's
 * column: "renderers[0] (sdl): camera.path: at most 100000 keys"; a probe
 * of session 46); 100000 pass. */
static void test_camera_path_keyframe_limit(void **state)
{
    static const char head[] =
        "{\"simulation\": {\"steps\": 1}, \"bodies\": [{\"name\": \"b\", \"type\": "
        "\"sphere\", \"radius\": 0.1, \"mass\": 1, \"position\": [0, 0, 1]}],\n"
        "\"renderers\": [{\"type\": \"sdl\", \"path\": \"p\", \"camera\": {\"path\": [";
    int counts[2] = {100000, 100001}, k;
    (void)state;
    for (k = 0; k < 2; k++) {
        char *text = malloc(sizeof head + (size_t)counts[k] * 64 + 16);
        size_t n = 0;
        int i;
        rbs_scene *scene = NULL;
        rbs_scene_error e;
        assert_non_null(text);
        n += (size_t)sprintf(text + n, "%s", head);
        for (i = 0; i < counts[k]; i++)
            n += (size_t)sprintf(text + n, "%s{\"t\": %d, \"position\": [3, -3, 2], "
                                 "\"target\": [0, 0, 0]}", i ? "," : "", i);
        n += (size_t)sprintf(text + n, "]}}]}");
        if (k == 0) {
            assert_int_equal(rbs_scene_parse_json(text, n, "k", &scene), RBS_OK);
        } else {
            assert_int_equal(rbs_scene_parse_json(text, n, "k", &scene), RBS_E_SCENE);
            assert_int_equal(rbs_scene_error_count(scene), 1);
            assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
            assert_string_equal(e.text, "k:2:63: renderers[0].camera.path: at most 100000 "
                                        "keyframes, got 100001");
        }
        rbs_scene_free(scene);
        free(text);
    }
}

/* Command-line overrides are validated like the file's values. */
static void test_override(void **state)
{
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    rbs_world_def def;
    (void)state;
    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_steps(scene), 3000);
    assert_int_equal(rbs_scene_override(scene, 0, 0.0, NULL), RBS_OK);
    assert_int_equal(rbs_scene_steps(scene), 3000);
    assert_int_equal(rbs_scene_override(scene, 10, 0.002, "rk4"), RBS_OK);
    assert_int_equal(rbs_scene_steps(scene), 10);
    assert_true(rbs_scene_dt(scene) == 0.002);
    assert_int_equal(rbs_scene_world_def(scene, &def), RBS_OK);
    assert_int_equal(def.method, RBS_METHOD_RK4);
    assert_true(def.dt == 0.002);

    /* bad values: an error each, the scene unchanged, and nothing runs */
    assert_int_equal(rbs_scene_override(scene, 0, 1.0 / 0.0, "rk5"), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 2);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --dt: must be a finite number > 0, got inf");
    assert_int_equal(rbs_scene_error_get(scene, 1, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --method: unknown method \"rk5\" (did you mean "
                                "\"rk4\"?); expected euler, selective, event, verlet, rk4, "
                                "adaptive, soft or auto");
    assert_int_equal(rbs_scene_steps(scene), 10);
    assert_true(rbs_scene_dt(scene) == 0.002);
    assert_int_equal(rbs_scene_world_def(scene, &def), RBS_E_SCENE);
    rbs_scene_free(scene);

    /* the capacities of a scene with no bodies (FORMAT.md, "Limits"): room
     * for one, and max_contacts 4 * 1 + 16 */
    {
        static const char empty[] = "{\"simulation\": {\"steps\": 1}, \"bodies\": []}";
        assert_int_equal(rbs_scene_parse_json(empty, sizeof empty - 1, "e", &scene), RBS_OK);
        assert_int_equal(rbs_scene_world_def(scene, &def), RBS_OK);
        assert_int_equal(def.max_bodies, 1);
        assert_int_equal(def.max_contacts, 20);
        rbs_scene_free(scene);
    }

    /* every method the library names is a valid override, "soft" among them */
    {
        int k;
        for (k = 0; k < RBS_METHOD_COUNT; k++) {
            const char *name = rbs_method_name((rbs_method)k);
            assert_non_null(name);
            assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json",
                                            RBS_SCENE_AUTO, &scene),
                             RBS_OK);
            assert_int_equal(rbs_scene_override(scene, 0, 0.0, name), RBS_OK);
            assert_int_equal(rbs_scene_world_def(scene, &def), RBS_OK);
            assert_int_equal(def.method, k);
            rbs_scene_free(scene);
        }
        assert_int_equal(rbs_method_from_name("soft", &def.method), RBS_OK);
        assert_int_equal(def.method, RBS_METHOD_SOFT);
    }

    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_override(scene, UINT64_MAX, 0.0, NULL), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --steps: must be at most 2^53, got "
                                "18446744073709551615");
    rbs_scene_free(scene);

    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_override(scene, 9007199254740992ULL, 1e300, NULL), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --steps: steps * dt overflows "
                                "(9007199254740992 * 1e+300)");
    rbs_scene_free(scene);

    /* dt alone makes it: named --dt (it said --steps; a probe of session 45) */
    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_override(scene, 0, 1e306, NULL), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_non_null(strstr(e.text, "command line: --dt: steps * dt overflows"));
    rbs_scene_free(scene);

    /* 2^53 + 1 is refused, not rounded to 2^53 */
    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_override(scene, 9007199254740993ULL, 0.0, NULL), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --steps: must be at most 2^53, got "
                                "9007199254740993");
    rbs_scene_free(scene);

    /* --slop: in (0, 0.1) reaches the world; else an error, the scene's
     * slop kept, and nothing builds */
    assert_int_equal(rbs_scene_override_slop(NULL, 0.01), RBS_E_INVALID);
    assert_int_equal(rbs_scene_load("../../scenes/bouncing_sphere.json", RBS_SCENE_AUTO, &scene),
                     RBS_OK);
    assert_int_equal(rbs_scene_override_slop(scene, 0.01), RBS_OK);
    assert_int_equal(rbs_scene_world_def(scene, &def), RBS_OK);
    assert_true(def.slop == 0.01);
    assert_int_equal(rbs_scene_override_slop(scene, 0.1), RBS_E_SCENE);
    assert_int_equal(rbs_scene_override_slop(scene, 0.0 / 0.0), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 2);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "command line: --slop: must be in (0, 0.1) (a fraction of the "
                                "smaller radius), got 0.1");
    assert_int_equal(rbs_scene_world_def(scene, &def), RBS_E_SCENE);
    rbs_scene_free(scene);
    assert_int_equal(rbs_scene_override(NULL, 1, 1, NULL), RBS_E_INVALID);
}

/* Renderer entries come back as JSON text; unknown types keep their keys. */
static void test_renderers(void **state)
{
    static const char text[] =
        "{\"simulation\": {\"steps\": 1},\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 1, \"mass\": 1,"
        " \"position\": [0, 0, 0]}],\n"
        " \"renderers\": [\n"
        "  {\"type\": \"csv\", \"path\": \"out/a.csv\"},\n"
        "  {\"type\": \"plotter\", \"pen\": \"blue\", \"nested\": {\"a\": [1, 2.5]}},\n"
        "  {\"type\": \"sdl\", \"views\": [{\"mount\": \"ball\", \"offset\": [0, 0, 2]},"
        " {\"mode\": \"fixed\", \"path\": [{\"t\": 0, \"position\": [1, 0, 0], \"target\": [0, 0, 0]}]}]}\n"
        " ]}\n";
    rbs_scene *scene = NULL;
    rbs_scene_renderer r;
    (void)state;
    assert_int_equal(rbs_scene_parse_json(text, sizeof text - 1, "r.json", &scene), RBS_OK);
    assert_int_equal(rbs_scene_renderer_count(scene), 3);
    assert_int_equal(rbs_scene_renderer_get(scene, 0, &r), RBS_OK);
    assert_string_equal(r.type, "csv");
    assert_string_equal(r.json, "{\"type\":\"csv\",\"path\":\"out/a.csv\"}");
    assert_string_equal(r.file, "r.json");
    assert_int_equal(r.line, 4);
    assert_int_equal(r.column, 3);
    assert_int_equal(rbs_scene_renderer_get(scene, 1, &r), RBS_OK);
    assert_string_equal(r.type, "plotter");
    assert_string_equal(r.json, "{\"type\":\"plotter\",\"pen\":\"blue\",\"nested\":{\"a\":[1,2.5]}}");
    assert_int_equal(rbs_scene_renderer_get(scene, 2, &r), RBS_OK);
    assert_string_equal(r.type, "sdl");
    assert_int_equal(rbs_scene_renderer_get(scene, 3, &r), RBS_E_NOT_FOUND);
    rbs_scene_free(scene);
}

/* A camera path's keyframes are checked where they are written, as the
 * sdl renderer would refuse them (which pointed at the renderer's entry):
 * a target at the keyframe's position, a view along up (sine below 1e-6);
 * and a path is for fixed cameras only, without a position or target of
 * the camera's own. */
static void test_camera_path_errors_at_the_keyframe(void **state)
{
    static const struct {
        const char *camera, *path, *message;
        const char *at; /* the error points at its last occurrence in camera */
    } cases[] = {
        {"{\"path\": [{\"t\": 0, \"position\": [1, 0, 0], \"target\": [0, 0, 0]}, "
         "{\"t\": 1, \"position\": [2, 0, 0], \"target\": [2, 0, 0]}]}",
         "renderers[0].camera.path[1].target", "must differ from the keyframe's position, got [2, 0, 0] for both",
         "[2, 0, 0]}"},
        {"{\"path\": [{\"t\": 0, \"position\": [0, 0, 5], \"target\": [0, 0, 0]}]}",
         "renderers[0].camera.path[0].target",
         "the view from the keyframe's position to [0, 0, 0] is along the camera's up; choose another "
         "target, position or up", "[0, 0, 0]}"},
        {"{\"mode\": \"free\", \"path\": [{\"t\": 0, \"position\": [1, 0, 0], \"target\": [0, 0, 0]}]}",
         "renderers[0].camera.path", "a free camera is steered from the keyboard; \"path\" is for fixed cameras",
         "\"path\""},
        {"{\"position\": [1, 1, 1], \"path\": [{\"t\": 0, \"position\": [1, 0, 0], \"target\": [0, 0, 0]}]}",
         "renderers[0].camera.path",
         "a camera with a path takes its position and target from the path: leave out \"position\"",
         "\"path\""},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[1024];
        rbs_scene *scene = NULL;
        rbs_scene_error e;
        snprintf(text, sizeof text,
                 "{\"simulation\": {\"steps\": 1}, \"bodies\": [],\n"
                 "\"renderers\": [{\"type\": \"sdl\", \"path\": \"p\", \"camera\":\n%s}]}\n",
                 cases[i].camera);
        assert_int_equal(rbs_scene_parse_json(text, strlen(text), "c.json", &scene), RBS_E_SCENE);
        assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
        if (strcmp(e.path, cases[i].path) != 0 || strcmp(e.message, cases[i].message) != 0)
            fail_msg("case %lu: '%s: %s'", (unsigned long)i, e.path, e.message);
        assert_int_equal(e.line, 3);
        {
            const char *at = NULL, *p = cases[i].camera;
            while ((p = strstr(p, cases[i].at)) != NULL)
                at = p++;
            assert_non_null(at);
            if (e.column != (int32_t)(at - cases[i].camera) + 1)
                fail_msg("case %lu: column %d, not %d", (unsigned long)i, (int)e.column,
                         (int)(at - cases[i].camera) + 1);
        }
        rbs_scene_free(scene);
    }
}

/* A renderer entry's numbers come back as the same doubles, in their
 * shortest exact form: 179.99999999999997 (the double below 180) is not
 * 180, which cJSON's own printing (%.15g when that reads back within a
 * relative DBL_EPSILON) made of it, and which the camera's check refuses. */
static void test_renderer_numbers_exact(void **state)
{
    static const char text[] =
        "{\"simulation\": {\"steps\": 1},\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 1, \"mass\": 1,"
        " \"position\": [0, 0, 0]}],\n"
        " \"renderers\": [\n"
        "  {\"type\": \"plotter\", \"a\": 179.99999999999997, \"b\": [0.1, 1e300, -0.0, 3000000000,"
        " 2.2250738585072014e-308, 4.9406564584124654e-324], \"c\": {\"d\": 1.0000000000000002}},\n"
        "  {\"type\": \"sdl\", \"window\": false, \"camera\": {\"fov\": 179.99999999999997}}\n"
        " ]}\n";
    rbs_scene *scene = NULL;
    rbs_scene_renderer r;
    (void)state;
    assert_int_equal(rbs_scene_parse_json(text, sizeof text - 1, "r.json", &scene), RBS_OK);
    assert_int_equal(rbs_scene_renderer_get(scene, 0, &r), RBS_OK);
    assert_string_equal(r.json, "{\"type\":\"plotter\",\"a\":179.99999999999997,\"b\":[0.1,1e+300,-0.0,3000000000,"
                                "2.2250738585072014e-308,5e-324],\"c\":{\"d\":1.0000000000000002}}");
    assert_int_equal(rbs_scene_renderer_get(scene, 1, &r), RBS_OK);
    assert_string_equal(r.json, "{\"type\":\"sdl\",\"window\":false,\"camera\":{\"fov\":179.99999999999997}}");
    rbs_scene_free(scene);
}

/* Names beyond ASCII: letters of any script are names; Unicode's spaces,
 * C1 controls and the invisible formatting characters (zero-width ones,
 * the bidirectional overrides and isolates that reorder a terminal's line)
 * are refused as ASCII's blanks and controls are, the code point named and
 * the echo showing '?' in its place, in a body's name and a material's. */
static void test_names_beyond_ascii(void **state)
{
    static const struct {
        const char *name; /* UTF-8 */
        const char *why;  /* NULL: a name */
    } cases[] = {
        {"kugel_\xc3\xa4", NULL},
        {"\xe7\x90\x83", NULL},
        {"\xce\xb2\xce\xb1\xce\xbb\xce\xbb", NULL},
        {"ball\xe2\x80\xae", "got \"ball?\" with U+202E (an invisible formatting character) at byte 5"},
        {"b\xe2\x81\xa6x", "got \"b?x\" with U+2066 (an invisible formatting character) at byte 2"},
        {"ba\xc2\xa0ll", "got \"ba?ll\" with U+00A0 (a space) at byte 3"},
        {"ba\xe2\x80\x8bll", "got \"ba?ll\" with U+200B (an invisible formatting character) at byte 3"},
        {"ball\xc2\x85", "got \"ball?\" with U+0085 (a control character) at byte 5"},
        {"a\xe2\x80\xa8z", "got \"a?z\" with U+2028 (a line or paragraph separator) at byte 2"},
        {"\xef\xbb\xbf" "ball", "got \"?ball\" with U+FEFF (an invisible formatting character) at byte 1"},
        {"\xe3\x80\x80", "got \"?\" with U+3000 (a space) at byte 1"},
    };
    size_t i;
    int where;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        for (where = 0; where < 2; where++) {
            char text[512], want[256];
            rbs_scene *scene = NULL;
            rbs_scene_error e;
            rbs_status st;
            if (where == 0)
                snprintf(text, sizeof text,
                         "{\"simulation\": {\"steps\": 1}, \"bodies\": [{\"name\": \"%s\", \"type\": \"sphere\","
                         " \"radius\": 1, \"mass\": 1, \"position\": [0, 0, 0]}]}",
                         cases[i].name);
            else
                snprintf(text, sizeof text,
                         "{\"simulation\": {\"steps\": 1}, \"materials\": [{\"pair\": [\"%s\", \"*\"],"
                         " \"static\": 1, \"kinetic\": 0.5}], \"bodies\": [{\"name\": \"b\", \"type\": \"sphere\","
                         " \"radius\": 1, \"mass\": 1, \"position\": [0, 0, 0], \"material\": \"%s\"}]}",
                         cases[i].name, cases[i].name);
            st = rbs_scene_parse_json(text, strlen(text), "n.json", &scene);
            if (cases[i].why == NULL) {
                if (st != RBS_OK && rbs_scene_error_get(scene, 0, &e) == RBS_OK)
                    fail_msg("case %lu/%d: %s", (unsigned long)i, where, e.text);
                assert_int_equal(st, RBS_OK);
            } else {
                assert_int_equal(st, RBS_E_SCENE);
                assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
                snprintf(want, sizeof want,
                         "a name must not contain spaces, control characters or invisible formatting "
                         "characters, %s",
                         cases[i].why);
                if (strcmp(e.message, want) != 0)
                    fail_msg("case %lu/%d: '%s', not '%s'", (unsigned long)i, where, e.message, want);
                assert_string_equal(e.path, where == 0 ? "bodies[0].name" : "materials[0].pair[0]");
            }
            rbs_scene_free(scene);
        }
    }
}

/* Text from the input echoed in an error is printed safely: a key (unknown,
 * in the key path) or a renderer type holding ESC,
 * DEL, a C1 control (U+009B, the one-byte CSI), a bidirectional override
 * (U+202E) shows each such
 * character as one '?' -- the whole error text, path and message, is
 * printable ASCII or UTF-8 without those -- while valid UTF-8 letters
 * (U+00E4, U+20AC) are kept.  Before, the key path and the CLI's "unknown
 * renderer type" were written raw: "simulation.fo\x1b[31mo" recoloured the
 * terminal. */
static void test_echoed_text_is_escaped(void **state)
{
    static const struct {
        const char *text;
        const char *path; /* the error's key path */
        const char *want; /* its message; NULL: not checked */
    } cases[] = {
        {"{\"simulation\": {\"steps\": 1, \"fo\\u001b[31mo\": 1}}", "simulation.\"fo?[31mo\"", NULL},
        {"{\"simulation\": {\"steps\": 1, \"fo\\u001b[2J\\u007fo\": 1}}", "simulation.\"fo?[2J?o\"", NULL},
        {"{\"simulation\": {\"steps\": 1, \"a\xc2\x9b" "31m\xe2\x80\xae" "b\": 1}}", "simulation.a?31m?b", NULL},
        {"{\"simulation\": {\"steps\": 1, \"k\xc3\xa4\xe2\x82\xac\": 1}}", "simulation.k\xc3\xa4\xe2\x82\xac", NULL},
        {"{\"simulation\": {\"steps\": 1, \"x\\u009b\": ", "simulation.x?", NULL},
        /* keys the path could not tell apart are quoted */
        {"{\"simulation\": {\"steps\": 1, \"\": 1}}", "simulation.\"\"", NULL},
        {"{\"simulation\": {\"steps\": 1, \"d.t\": 1}}", "simulation.\"d.t\"", NULL},
        {"{\"simulation\": {\"steps\": 1, \"d t\": 1}}", "simulation.\"d t\"", NULL},
        {"{\"simulation\": {\"steps\": 1, \"a[0]\": 1}}", "simulation.\"a[0]\"", NULL},
        {"{\"simulation\": {\"steps\": 1}, \"renderers\": [{\"type\": \"\\u001b]0;t\\u0007\", \"path\": \"p\"}]}",
         "renderers[0].type",
         "a name must not contain spaces, control characters, '#', '\"', '=' or ',', got \"?]0;t?\""},
        {"{\"simulation\": {\"steps\": 1}, \"renderers\": [{\"type\": \"my\xe2\x80\xaerend\", \"path\": \"p\"}]}",
         "renderers[0].type",
         "a name must not contain spaces, control characters or invisible formatting characters, got "
         "\"my?rend\" with U+202E (an invisible formatting character) at byte 3"},
    };
    size_t i, k;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        rbs_scene *scene = NULL;
        rbs_scene_error e;
        assert_int_equal(rbs_scene_parse_json(cases[i].text, strlen(cases[i].text), "e.json", &scene),
                         RBS_E_SCENE);
        /* (the error at that path; others, such as a missing "bodies", may come first) */
        for (k = 0; rbs_scene_error_get(scene, k, &e) == RBS_OK; k++)
            if (strcmp(e.path, cases[i].path) == 0)
                break;
        if (strcmp(e.path, cases[i].path) != 0)
            fail_msg("case %lu: no error at '%s' (last: '%s')", (unsigned long)i, cases[i].path, e.text);
        if (cases[i].want != NULL && strcmp(e.message, cases[i].want) != 0)
            fail_msg("case %lu: '%s', not '%s'", (unsigned long)i, e.message, cases[i].want);
        for (k = 0; e.text[k] != '\0'; k++) {
            unsigned char c = (unsigned char)e.text[k];
            if (c < 0x20 || c == 0x7f || (c == 0xc2 && (unsigned char)e.text[k + 1] < 0xa0) ||
                (c == 0xe2 && (unsigned char)e.text[k + 1] == 0x80 && (unsigned char)e.text[k + 2] == 0xae))
                fail_msg("case %lu: a raw control or override at byte %lu of '%s'", (unsigned long)i,
                         (unsigned long)k, e.text);
        }
        rbs_scene_free(scene);
    }
}

/* A material named in a "materials" row that no body has: the scene loads
 * and builds (a material exists by being named in a row), with a warning
 * at the material's first row, once, suggesting the closest material a
 * body has.  The typo "stel" beside "steel" left the ball on the "*" row
 * (mu 0.5, not the steel/rubber row's 0.9) and `rbsim check` said "ok"
 * (a probe of session 50).  A scene whose every material is on a body,
 * and a scene with errors, warn of nothing else. */
static void test_unused_material_warns(void **state)
{
    static const char typo[] =
        "{\"format\": 1, \"simulation\": {\"steps\": 1},\n"
        " \"materials\": [{\"pair\": [\"steel\", \"rubber\"], \"static\": 0.9, \"kinetic\": 0.8},\n"
        "  {\"pair\": [\"stel\", \"rubber\"], \"static\": 0.1, \"kinetic\": 0.1},\n"
        "  {\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3},\n"
        "  {\"pair\": [\"stel\", \"glass\"], \"static\": 0.5, \"kinetic\": 0.3}],\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 1,"
        " \"position\": [0, 0, 1], \"material\": \"steel\"},\n"
        "  {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
        " \"material\": \"rubber\"}]}\n";
    rbs_scene *scene = NULL;
    rbs_world *world = NULL;
    rbs_scene_error e;
    (void)state;
    assert_int_equal(rbs_scene_parse_json(typo, strlen(typo), "typo.json", &scene), RBS_OK);
    assert_int_equal(rbs_scene_error_count(scene), 0);
    assert_int_equal(rbs_scene_warning_count(scene), 2);
    assert_int_equal(rbs_scene_warning_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "typo.json:3:13: materials[1].pair[0]: material \"stel\" is on "
                                "no body, so this row applies to no contact (did you mean "
                                "\"steel\"?)");
    assert_string_equal(e.file, "typo.json");
    assert_string_equal(e.path, "materials[1].pair[0]");
    assert_int_equal(e.line, 3);
    assert_int_equal(e.column, 13);
    /* "stel" once (its first row); "glass", with nothing close on a body */
    assert_int_equal(rbs_scene_warning_get(scene, 1, &e), RBS_OK);
    assert_string_equal(e.text, "typo.json:5:21: materials[3].pair[1]: material \"glass\" is on "
                                "no body, so this row applies to no contact");
    assert_int_equal(rbs_scene_warning_get(scene, 2, &e), RBS_E_NOT_FOUND);
    assert_int_equal(rbs_scene_warning_get(scene, 0, NULL), RBS_E_INVALID);
    assert_int_equal(rbs_scene_warning_get(NULL, 0, &e), RBS_E_INVALID);
    assert_int_equal(rbs_scene_warning_count(NULL), 0);
    /* a warning does not stop the world */
    assert_int_equal(rbs_scene_build(scene, &world), RBS_OK);
    rbs_world_destroy(world);
    rbs_scene_free(scene);
    /* every material on a body: no warning (the demonstration scenes too) */
    {
        static const char fine[] =
            "{\"format\": 1, \"simulation\": {\"steps\": 1},"
            " \"materials\": [{\"pair\": [\"steel\", \"rubber\"], \"static\": 0.9, \"kinetic\": 0.8},"
            " {\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3}],"
            " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 1,"
            " \"position\": [0, 0, 1], \"material\": \"steel\"},"
            " {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
            " \"material\": \"rubber\"}]}";
        char path[64];
        size_t k;
        scene = NULL;
        assert_int_equal(rbs_scene_parse_json(fine, strlen(fine), "fine.json", &scene), RBS_OK);
        assert_int_equal(rbs_scene_warning_count(scene), 0);
        rbs_scene_free(scene);
        for (k = 0; k < DEMO_COUNT; k++) {
            snprintf(path, sizeof path, "../../scenes/%s.json", demo_names[k]);
            scene = NULL;
            assert_int_equal(rbs_scene_load(path, RBS_SCENE_AUTO, &scene), RBS_OK);
            if (rbs_scene_warning_count(scene) != 0)
                fail_msg("%s warns", path);
            rbs_scene_free(scene);
        }
    }
}

/* Materials: "*" rows cover missing pairs; a body without material matches
 * only "*" rows; a sphere resting on a plane (gap 0) is not an overlap. */
static void test_material_rules(void **state)
{
    static const char ok_text[] =
        "{\"simulation\": {\"steps\": 1},\n"
        " \"materials\": [{\"pair\": [\"rubber\", \"*\"], \"static\": 1, \"kinetic\": 0.5}],\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.5, \"mass\": 1,"
        " \"position\": [0, 0, 0.5], \"material\": \"rubber\"},\n"
        " {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 2]}]}\n";
    static const char bad_text[] =
        "{\"simulation\": {\"steps\": 1},\n"
        " \"materials\": [{\"pair\": [\"rubber\", \"rubber\"], \"static\": 1, \"kinetic\": 0.5}],\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.5, \"mass\": 1,"
        " \"position\": [0, 0, 0.5], \"material\": \"rubber\"},\n"
        " {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1]}]}\n";
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_int_equal(rbs_scene_parse_json(ok_text, sizeof ok_text - 1, "ok", &scene), RBS_OK);
    rbs_scene_free(scene);
    assert_int_equal(rbs_scene_parse_json(bad_text, sizeof bad_text - 1, "bad", &scene),
                     RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_string_equal(e.text, "bad:4:2: bodies[1].name: no material pair for [\"rubber\", "
                                "\"(no material)\"]: bodies \"ball\" and \"floor\" could touch; "
                                "add the pair or a \"*\" row to \"materials\"");
    rbs_scene_free(scene);
}

/* The "event" method's scope decided at load (rbs_scene_override with
 * "event" here) agrees with its step's own check: a scene is refused at
 * load exactly when the world built from it with another method, switched
 * to "event", refuses its first step as RBS_E_UNSUPPORTED. */
static void test_event_scope_agrees_with_the_step(void **state)
{
#define EV_SIM "{\"simulation\": {\"steps\": 1, \"gravity\": [0, 0, 0]"
#define EV_BALL(name, x, extra)                                                              \
    "{\"name\": \"" name "\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 1, "           \
    "\"position\": [" x ", 0, 1]" extra "}"
#define EV_FLOOR(extra) \
    "{\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1]" extra "}"
    static const char *const texts[] = {
        /* 0: within the scope */
        EV_SIM "}, \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3}],"
        " \"bodies\": [" EV_BALL("a", "0", "") ", " EV_FLOOR("") "]}",
        /* 1: mutual gravity */
        EV_SIM ", \"mutual_gravity\": true}, \"materials\": [{\"pair\": [\"*\", \"*\"], "
        "\"static\": 0.5, \"kinetic\": 0.3}], \"bodies\": [" EV_BALL("a", "0", "") ", "
        EV_BALL("b", "1", "") "]}",
        /* 2: rolling on the row every contact takes */
        EV_SIM "}, \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3, "
        "\"rolling\": 0.01}], \"bodies\": [" EV_BALL("a", "0", "") ", " EV_FLOOR("") "]}",
        /* 3: spinning on a row of a material no body has */
        EV_SIM "}, \"materials\": [{\"pair\": [\"ice\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3, "
        "\"spinning\": 0.01}, {\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3}],"
        " \"bodies\": [" EV_BALL("a", "0", "") ", " EV_FLOOR("") "]}",
        /* 4: rolling on a "*" row that exact pairs shadow (the sphere's
         * material with itself among them) */
        EV_SIM "}, \"materials\": [{\"pair\": [\"rubber\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3, "
        "\"rolling\": 0.01}, {\"pair\": [\"rubber\", \"wood\"], \"static\": 0.5, \"kinetic\": 0.3}, "
        "{\"pair\": [\"rubber\", \"rubber\"], \"static\": 0.5, \"kinetic\": 0.3}],"
        " \"bodies\": [" EV_BALL("a", "0", ", \"material\": \"rubber\"") ", "
        EV_FLOOR(", \"material\": \"wood\"") "]}",
        /* 5: rolling on the pair of a moving sphere's material with itself
         * (one sphere of it: the world counts the pair all the same) */
        EV_SIM "}, \"materials\": [{\"pair\": [\"rubber\", \"rubber\"], \"static\": 0.5, "
        "\"kinetic\": 0.3, \"rolling\": 0.01}, {\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
        "\"kinetic\": 0.3}], \"bodies\": [" EV_BALL("a", "0", ", \"material\": \"rubber\"") ", "
        EV_FLOOR("") "]}",
        /* 6: rolling on a pair of two materials of fixed bodies only */
        EV_SIM "}, \"materials\": [{\"pair\": [\"steel\", \"wood\"], \"static\": 0.5, "
        "\"kinetic\": 0.3, \"rolling\": 0.01}, {\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
        "\"kinetic\": 0.3}], \"bodies\": [" EV_BALL("a", "0", "") ", "
        EV_BALL("s", "1", ", \"fixed\": true, \"material\": \"steel\"") ", "
        EV_FLOOR(", \"material\": \"wood\"") "]}",
        /* 7, 8, 9: anisotropic inertia, moving and fixed; equal moments */
        EV_SIM "}, \"bodies\": [" EV_BALL("a", "0", ", \"inertia\": [0.004, 0.004, 0.005]") "]}",
        EV_SIM "}, \"bodies\": [" EV_BALL("a", "0", ", \"inertia\": [0.004, 0.004, 0.005], "
                                               "\"fixed\": true") "]}",
        EV_SIM "}, \"bodies\": [" EV_BALL("a", "0", ", \"inertia\": [0.004, 0.004, 0.004]") "]}",
        /* 10, 11: an off-centre mass; -0 is the centre */
        EV_SIM "}, \"bodies\": [" EV_BALL("a", "0", ", \"center_of_mass\": [0, 1e-300, 0]") "]}",
        EV_SIM "}, \"bodies\": [" EV_BALL("a", "0", ", \"center_of_mass\": [-0.0, 0, -0.0]") "]}",
        /* 12, 13, 14: mutual gravity that cannot act -- one sphere; two,
         * none moving -- and that can, a moving sphere and a fixed one
         * (the check refused it whatever the bodies, the step took the
         * first two: a probe of session 46) */
        EV_SIM ", \"mutual_gravity\": true}, \"bodies\": [" EV_BALL("a", "0", "") "]}",
        EV_SIM ", \"mutual_gravity\": true}, \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
        "\"kinetic\": 0.3}], \"bodies\": [" EV_BALL("a", "0", ", \"fixed\": true") ", "
        EV_BALL("b", "1", ", \"fixed\": true") "]}",
        EV_SIM ", \"mutual_gravity\": true}, \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
        "\"kinetic\": 0.3}], \"bodies\": [" EV_BALL("a", "0", "") ", "
        EV_BALL("b", "1", ", \"fixed\": true") "]}",
    };
    static const int refused[] = {0, 1, 1, 0, 0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 1};
    size_t k;
    (void)state;
    for (k = 0; k < sizeof texts / sizeof *texts; k++) {
        rbs_scene *scene = NULL;
        rbs_world *world = NULL;
        rbs_status st;
        assert_int_equal(rbs_scene_parse_json(texts[k], strlen(texts[k]), "ev", &scene), RBS_OK);
        assert_int_equal(rbs_scene_build(scene, &world), RBS_OK);
        assert_int_equal(rbs_world_set_method(world, RBS_METHOD_EVENT, 0.0), RBS_OK);
        st = rbs_world_step(world, NULL);
        if (st != (refused[k] ? RBS_E_UNSUPPORTED : RBS_OK))
            fail_msg("scene %lu: the step says %s", (unsigned long)k, rbs_status_string(st));
        st = rbs_scene_override(scene, 0, 0.0, "event");
        if (st != (refused[k] ? RBS_E_SCENE : RBS_OK))
            fail_msg("scene %lu: the override says %s", (unsigned long)k, rbs_status_string(st));
        rbs_world_destroy(world);
        rbs_scene_free(scene);
    }
    /* and every demonstration scene: the two agree */
    for (k = 0; k < DEMO_COUNT; k++) {
        char path[256];
        rbs_scene *scene = NULL;
        rbs_world *world = NULL;
        rbs_status step, load;
        snprintf(path, sizeof path, "../../scenes/%s.json", demo_names[k]);
        assert_int_equal(rbs_scene_load(path, RBS_SCENE_AUTO, &scene), RBS_OK);
        assert_int_equal(rbs_scene_build(scene, &world), RBS_OK);
        assert_int_equal(rbs_world_set_method(world, RBS_METHOD_EVENT, 0.0), RBS_OK);
        step = rbs_world_step(world, NULL);
        load = rbs_scene_override(scene, 0, 0.0, "event");
        if ((step == RBS_E_UNSUPPORTED) != (load == RBS_E_SCENE))
            fail_msg("%s: the step says %s, the override %s", path, rbs_status_string(step),
                     rbs_status_string(load));
        rbs_world_destroy(world);
        rbs_scene_free(scene);
    }
#undef EV_SIM
#undef EV_BALL
#undef EV_FLOOR
}

/* simulation.slop reaches the world, and is the overlap a scene may start
 * with: a ball 0.4 % of its radius inside the floor loads with slop 0.005
 * and is an error with the world's default (1e-6); absent, the world's
 * default is what the world gets.  simulation.max_sweeps,
 * simulation.soft_substeps and simulation.soft_tolerance reach it too. */
static void test_slop(void **state)
{
    static const char fmt[] =
        "{\"simulation\": {\"steps\": 1%s},\n"
        " \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3}],\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.5, \"mass\": 1,"
        " \"position\": [0, 0, %s]},\n"
        " {\"name\": \"floor\", \"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1]}]}\n";
    char text[1024];
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    rbs_world_def d, def0;
    (void)state;
    rbs_world_def_init(&def0);
    snprintf(text, sizeof text, fmt, ", \"slop\": 0.005", "0.498");
    assert_int_equal(rbs_scene_parse_json(text, strlen(text), "loose", &scene), RBS_OK);
    assert_int_equal(rbs_scene_world_def(scene, &d), RBS_OK);
    assert_true(d.slop == 0.005);
    rbs_scene_free(scene);
    snprintf(text, sizeof text, fmt, "", "0.498");
    assert_int_equal(rbs_scene_parse_json(text, strlen(text), "tight", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_non_null(strstr(e.text, "bodies[0].position: \"ball\" starts behind (inside) plane"));
    rbs_scene_free(scene);
    snprintf(text, sizeof text, fmt, "", "0.5");
    assert_int_equal(rbs_scene_parse_json(text, strlen(text), "default", &scene), RBS_OK);
    assert_int_equal(rbs_scene_world_def(scene, &d), RBS_OK);
    assert_true(d.slop == def0.slop);
    assert_int_equal(d.max_sweeps, def0.max_sweeps);
    assert_int_equal(d.soft_substeps, def0.soft_substeps);
    assert_int_equal(d.soft_substeps, 3);
    assert_true(d.soft_tolerance == def0.soft_tolerance);
    assert_true(d.soft_tolerance == 0.0);
    rbs_scene_free(scene);
    /* simulation.max_sweeps likewise */
    snprintf(text, sizeof text, fmt, ", \"max_sweeps\": 5", "0.5");
    assert_int_equal(rbs_scene_parse_json(text, strlen(text), "sweeps", &scene), RBS_OK);
    assert_int_equal(rbs_scene_world_def(scene, &d), RBS_OK);
    assert_int_equal(d.max_sweeps, 5);
    assert_int_equal(d.max_contacts, 4 * 2 + 16); /* (the default: 4 x bodies + 16) */
    rbs_scene_free(scene);
    /* simulation.max_contacts: from 1 to the world's 2^26; the world gets it */
    snprintf(text, sizeof text, fmt, ", \"max_contacts\": 67108864", "0.5");
    assert_int_equal(rbs_scene_parse_json(text, strlen(text), "contacts", &scene), RBS_OK);
    assert_int_equal(rbs_scene_world_def(scene, &d), RBS_OK);
    assert_int_equal(d.max_contacts, 67108864);
    rbs_scene_free(scene);
    {
        static const char *const bad[] = {"0", "2.5", "67108865", "-1", "\"many\""};
        size_t i;
        for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
            char extra[64], want[160];
            snprintf(extra, sizeof extra, ", \"max_contacts\": %s", bad[i]);
            snprintf(text, sizeof text, fmt, extra, "0.5");
            assert_int_equal(rbs_scene_parse_json(text, strlen(text), "contacts", &scene), RBS_E_SCENE);
            assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
            snprintf(want, sizeof want, "simulation.max_contacts: must be an integer from 1 to 67108864 (2^26), got %s",
                     bad[i]);
            if (strstr(e.text, want) == NULL)
                fail_msg("'%s' does not hold '%s'", e.text, want);
            rbs_scene_free(scene);
        }
    }
    /* simulation.soft_substeps and soft_tolerance likewise, at both ends of
     * their ranges and between, and the world takes them */
    {
        static const struct {
            const char *json;
            uint32_t n;
            double tol;
        } cases[] = {{"\"soft_substeps\": 1", 1, 0.0},          {"\"soft_substeps\": 13", 13, 0.0},
                     {"\"soft_substeps\": 1000", 1000, 0.0},    {"\"soft_tolerance\": 0", 3, 0.0},
                     {"\"soft_tolerance\": 0.015625", 3, 0.015625}, {"\"soft_tolerance\": 1", 3, 1.0}};
        size_t i;
        for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
            char key[80];
            rbs_world *world = NULL;
            rbs_world_def got;
            snprintf(key, sizeof key, ", \"method\": \"soft\", %s", cases[i].json);
            snprintf(text, sizeof text, fmt, key, "0.5");
            assert_int_equal(rbs_scene_parse_json(text, strlen(text), "soft", &scene), RBS_OK);
            assert_int_equal(rbs_scene_world_def(scene, &d), RBS_OK);
            assert_int_equal(d.soft_substeps, cases[i].n);
            assert_true(d.soft_tolerance == cases[i].tol);
            assert_int_equal(d.method, RBS_METHOD_SOFT);
            assert_int_equal(rbs_scene_build(scene, &world), RBS_OK);
            rbs_world_def_init(&got);
            assert_int_equal(rbs_world_get_def(world, &got), RBS_OK);
            assert_int_equal(got.soft_substeps, cases[i].n);
            assert_true(got.soft_tolerance == cases[i].tol);
            rbs_world_destroy(world);
            rbs_scene_free(scene);
        }
    }
}

/* Overlap at the start is found wherever the two spheres are in the body
 * list and whatever their sizes (the grid's levels): a lattice of 1000
 * spheres, no planes, where the last overlaps the first; then a tiny sphere
 * inside a huge one, listed first and last. */
static void test_overlap_far_apart(void **state)
{
    size_t cap = 200000, n = 0;
    char *text = malloc(cap);
    int i;
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    (void)state;
    assert_non_null(text);
    n += (size_t)snprintf(text + n, cap - n,
                          "{\"simulation\": {\"steps\": 1, \"gravity\": [0, 0, 0]},\n"
                          "\"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
                          "\"kinetic\": 0.3}],\n\"bodies\": [\n");
    for (i = 0; i < 1000; i++) {
        /* a 10 x 10 x 10 lattice, 1 m apart, radius 0.4; the last at the first's place */
        int x = i % 10, y = (i / 10) % 10, z = i / 100;
        if (i == 999) {
            x = y = 0;
            z = 0;
        }
        n += (size_t)snprintf(text + n, cap - n,
                              "%s{\"name\": \"b%d\", \"type\": \"sphere\", \"radius\": 0.4, "
                              "\"mass\": 1, \"position\": [%d, %d, %d.25]}\n",
                              i ? "," : "", i, x, y, z);
    }
    n += (size_t)snprintf(text + n, cap - n, "]}\n");
    assert_int_equal(rbs_scene_parse_json(text, n, "lattice", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_non_null(strstr(e.text, "bodies[999].position: \"b999\" overlaps \"b0\" (bodies[0]) "
                                   "by 0.8 m at the start"));
    rbs_scene_free(scene);

    n = (size_t)snprintf(text, cap,
                         "{\"simulation\": {\"steps\": 1, \"gravity\": [0, 0, 0]},\n"
                         "\"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, "
                         "\"kinetic\": 0.3}],\n\"bodies\": [\n"
                         "{\"name\": \"tiny\", \"type\": \"sphere\", \"radius\": 1e-3, "
                         "\"mass\": 1, \"position\": [-900, 0, 0]},\n"
                         "{\"name\": \"far\", \"type\": \"sphere\", \"radius\": 1, "
                         "\"mass\": 1, \"position\": [5000, 0, 0]},\n"
                         "{\"name\": \"huge\", \"type\": \"sphere\", \"radius\": 1000, "
                         "\"mass\": 1, \"position\": [0, 0, 0]}]}\n");
    assert_int_equal(rbs_scene_parse_json(text, n, "sizes", &scene), RBS_E_SCENE);
    assert_int_equal(rbs_scene_error_count(scene), 1);
    assert_int_equal(rbs_scene_error_get(scene, 0, &e), RBS_OK);
    assert_non_null(strstr(e.text, "bodies[2].position: \"huge\" overlaps \"tiny\" (bodies[0])"));
    rbs_scene_free(scene);
    free(text);
}

/* A normal or quaternion whose squared length overflows or underflows is
 * still a direction: [0, 0, 1e308], [1e-200, 1e-200, 0], [0, 0, 5e-324] and
 * the quaternion [1e308, 1e308, 0, 0] load (they were "must be a nonzero
 * vector of finite length"), and the world built from them has the unit
 * ones, as rbs_world_add_plane makes of the same input.  Tolerance: the
 * scene and the world each divide by a length (2 roundings of 1/2 ulp on a
 * component below 1), so 2 ulp of 1, 4.5e-16. */
static void test_huge_and_tiny_directions(void **state)
{
    static const char text[] =
        "{\"simulation\": {\"steps\": 1, \"gravity\": [0, 0, 0]},\n"
        " \"materials\": [{\"pair\": [\"*\", \"*\"], \"static\": 0.5, \"kinetic\": 0.3}],\n"
        " \"bodies\": [{\"name\": \"ball\", \"type\": \"sphere\", \"radius\": 0.1, \"mass\": 1,"
        " \"position\": [0, 0, 0], \"orientation\": [1e308, 1e308, 0, 0]},\n"
        " {\"name\": \"huge\", \"type\": \"plane\", \"point\": [0, 0, -10], \"normal\": [0, 0, 1e308]},\n"
        " {\"name\": \"tiny\", \"type\": \"plane\", \"point\": [-10, -10, 0], \"normal\": [1e-200, 1e-200, 0]},\n"
        " {\"name\": \"sub\", \"type\": \"plane\", \"point\": [0, 0, -20], \"normal\": [0, 0, 5e-324]}]}\n";
    const double h = 0.70710678118654752440, tol = 4.5e-16;
    rbs_scene *scene = NULL;
    rbs_scene_error e;
    rbs_world *w = NULL;
    rbs_body_id id;
    rbs_body_state b;
    rbs_status st;
    (void)state;
    st = rbs_scene_parse_json(text, sizeof text - 1, "dirs.json", &scene);
    if (st != RBS_OK && rbs_scene_error_get(scene, 0, &e) == RBS_OK)
        fail_msg("%s", e.text);
    assert_int_equal(st, RBS_OK);
    assert_int_equal(rbs_scene_build(scene, &w), RBS_OK);
    assert_int_equal(rbs_world_find_body(w, "ball", &id), RBS_OK);
    assert_int_equal(rbs_body_get_state(w, id, &b), RBS_OK);
    assert_true(fabs(b.orientation.w - h) <= tol && fabs(b.orientation.x - h) <= tol);
    assert_true(b.orientation.y == 0.0 && b.orientation.z == 0.0);
    assert_int_equal(rbs_world_find_body(w, "huge", &id), RBS_OK);
    assert_int_equal(rbs_body_get_state(w, id, &b), RBS_OK);
    assert_true(b.normal.x == 0.0 && b.normal.y == 0.0 && b.normal.z == 1.0);
    assert_int_equal(rbs_world_find_body(w, "tiny", &id), RBS_OK);
    assert_int_equal(rbs_body_get_state(w, id, &b), RBS_OK);
    assert_true(fabs(b.normal.x - h) <= tol && fabs(b.normal.y - h) <= tol && b.normal.z == 0.0);
    assert_int_equal(rbs_world_find_body(w, "sub", &id), RBS_OK);
    assert_int_equal(rbs_body_get_state(w, id, &b), RBS_OK);
    assert_true(b.normal.x == 0.0 && b.normal.y == 0.0 && b.normal.z == 1.0);
    rbs_world_destroy(w);
    rbs_scene_free(scene);
}

/* rbs_scene_suggest: the scene's "did you mean" rule, public for front
 * ends (the command's renderer types and scene paths): max(2, len / 3)
 * edits, else an abbreviation of 3 bytes or more; the first of equals. */
static void test_suggest(void **state)
{
    static const char *const types[] = {"csv", "json", "stats", "sdl"};
    static const char *const files[] = {"bouncing_sphere.json", "incline.json", "orbit.json"};
    static const char *const twins[] = {"ab", "ba"};
    const char *const with_null[] = {"csv", NULL};
    (void)state;
    assert_string_equal(rbs_scene_suggest("cvs", types, 4), "csv");
    assert_string_equal(rbs_scene_suggest("jsn", types, 4), "json");
    assert_string_equal(rbs_scene_suggest("stat", types, 4), "stats");
    assert_null(rbs_scene_suggest("pngs", types, 4));
    assert_string_equal(rbs_scene_suggest("bouncing_sphre.json", files, 3), "bouncing_sphere.json");
    assert_string_equal(rbs_scene_suggest("incl", files, 3), "incline.json"); /* an abbreviation */
    assert_null(rbs_scene_suggest("collisions.json", files, 3));
    assert_string_equal(rbs_scene_suggest("aa", twins, 2), "ab"); /* one edit each: the first */
    assert_null(rbs_scene_suggest(NULL, types, 4));
    assert_null(rbs_scene_suggest("csv", NULL, 4));
    assert_null(rbs_scene_suggest("csv", with_null, 2));
    assert_null(rbs_scene_suggest("csv", types, 0));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_files),      cmocka_unit_test(test_error_fields), cmocka_unit_test(test_suggest),
        cmocka_unit_test(test_unreadable),     cmocka_unit_test(test_error_limit),
        cmocka_unit_test(test_override),       cmocka_unit_test(test_renderers), cmocka_unit_test(test_renderer_numbers_exact),
        cmocka_unit_test(test_names_beyond_ascii),
        cmocka_unit_test(test_camera_path_errors_at_the_keyframe),
        cmocka_unit_test(test_camera_path_keyframe_limit),
        cmocka_unit_test(test_echoed_text_is_escaped),
        cmocka_unit_test(test_material_rules), cmocka_unit_test(test_slop),
        cmocka_unit_test(test_unused_material_warns),
        cmocka_unit_test(test_event_scope_agrees_with_the_step),
        cmocka_unit_test(test_overlap_far_apart), cmocka_unit_test(test_huge_and_tiny_directions),
    };
    if (enter_test_dir() != 0) {
        return 1;
    }
    return cmocka_run_group_tests_name("scene_errors", tests, NULL, NULL);
}
