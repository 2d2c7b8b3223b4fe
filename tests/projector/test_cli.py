"""Drive the built rbsim command and check what it writes.

Run as: python test_cli.py SUITE  (SUITE: cli, fault, determinism), with the
environment variables RBSIM (the rbsim binary) and CSV_TRUTH (the csv_truth
helper).  Each test works in its own temporary folder.
"""
import csv
import json
import math
import re
import os
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

RBSIM = os.environ.get("RBSIM", "rbsim")
CSV_TRUTH = os.environ.get("CSV_TRUTH", "csv_truth")

CSV_HEADER = ("frame,t,body,name,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz")
STATS_HEADER = ("frame,t,kinetic,potential,total,px,py,pz,lx,ly,lz,"
                "max_overlap,contacts,collisions,substeps,rollbacks,work_limit")

SCENE = {
    "format": 1,
    "simulation": {"steps": 300, "dt": 0.001},
    "materials": [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3,
                   "restitution": 0.7}],
    "bodies": [
        {"name": "floor", "type": "plane", "point": [0, 0, 0],
         "normal": [0, 0, 1]},
        {"name": "a", "type": "sphere", "radius": 0.1, "mass": 1,
         "position": [0, 0, 0.5], "velocity": [1, 0, 0]},
        {"name": "b", "type": "sphere", "radius": 0.1, "mass": 1,
         "position": [0.5, 0, 0.3], "velocity": [-1, 0.2, 0]},
        {"name": "c", "type": "sphere", "radius": 0.05, "mass": 0.3,
         "position": [1, 1, 0.05], "angular_velocity": [0, 0, 10]},
    ],
}
BODIES = 4


def bits(x):
    return struct.pack("<d", x)


def file_size_limit(limit, on_sigxfsz):
    """A preexec_fn: a file size limit of `limit` bytes (ulimit -f), with
    SIGXFSZ at on_sigxfsz (rbsim ignores it itself; SIG_DFL is its death)."""
    def apply():
        signal.signal(signal.SIGXFSZ, on_sigxfsz)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return apply


class Base(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="rbsim-cli-")
        self.dir = self._tmp.name

    def tearDown(self):
        self._tmp.cleanup()

    def path(self, name):
        return os.path.join(self.dir, name)

    def scene(self, name="scene.json", **changes):
        s = json.loads(json.dumps(SCENE))
        for k, v in changes.items():
            s[k] = v
        p = self.path(name)
        with open(p, "w") as f:
            json.dump(s, f, indent=1)
        return p

    def rbsim(self, *args, stdin=subprocess.DEVNULL, timeout=120, **kw):
        return subprocess.run([RBSIM] + list(args), stdin=stdin,
                              capture_output=True, text=True, cwd=self.dir,
                              timeout=timeout, **kw)

    def read_csv(self, p):
        with open(p, newline="") as f:
            rows = list(csv.reader(f))
        self.assertEqual(",".join(rows[0]), CSV_HEADER)
        return rows[1:]

    def assert_whole_frames(self, p, first=0):
        """The CSV ends on a newline and holds whole frames first..n, in
        order, each with every body once."""
        with open(p, "rb") as f:
            data = f.read()
        self.assertTrue(data.endswith(b"\n"), "%s ends mid-line" % p)
        rows = self.read_csv(p)
        self.assertEqual(len(rows) % BODIES, 0, "a frame is cut short")
        for i, r in enumerate(rows):
            self.assertEqual(len(r), 17, "row %d: %r" % (i, r))
            self.assertEqual(int(r[0]), first + i // BODIES)
            self.assertEqual(int(r[2]), i % BODIES)
        return len(rows) // BODIES


class CliTests(Base):
    def test_version_and_help(self):
        r = self.rbsim("--version")
        self.assertEqual(r.returncode, 0)
        self.assertRegex(r.stdout, r"^rbsim \d+\.\d+\.\d+ \(library ")
        for args in (["help"], ["--help"], ["help", "run"], ["help", "check"],
                     ["help", "convert"]):
            r = self.rbsim(*args)
            self.assertEqual(r.returncode, 0, args)
            self.assertIn("usage: rbsim", r.stdout)
        self.assertIn("--csv FILE", self.rbsim("help", "run").stdout)
        self.assertIn("step [N]", self.rbsim("help", "run").stdout)
        self.assertEqual(self.rbsim("help", "nope").returncode, 2)
        self.assertEqual(self.rbsim().returncode, 2)
        r = self.rbsim("frobnicate")
        self.assertEqual(r.returncode, 2)
        self.assertIn("unknown command 'frobnicate'", r.stderr)

    def test_help_wins_over_version(self):
        # "rbsim --version --help" was refused (exit 2, "takes no
        # arguments") and "rbsim --help --version" said "help: unknown
        # command '--version'".  --help (or -h) wins wherever it is among
        # the top-level flags, as in GNU tools; a COMMAND after them is
        # help's.
        usage = self.rbsim("help").stdout
        for args in (["--version", "--help"], ["--help", "--version"],
                     ["-h", "--version"], ["--version", "-h", "--version"],
                     ["--help", "--help"]):
            r = self.rbsim(*args)
            self.assertEqual((r.returncode, r.stdout, r.stderr),
                             (0, usage, ""), args)
        r = self.rbsim("--version", "--help", "run")
        self.assertEqual((r.returncode, r.stdout),
                         (0, self.rbsim("help", "run").stdout))
        r = self.rbsim("--version", "--version")
        self.assertEqual(r.returncode, 2)
        self.assertIn("takes no arguments", r.stderr)
        self.assertIn("with --help as well", usage)

    def test_help_after_a_command(self):
        # "rbsim run --help" (or -h, for each command) was "unknown option"
        # with exit 2; only "rbsim help run" worked.  It prints exactly what
        # "rbsim help COMMAND" prints, on stdout, exit 0 -- also among other
        # arguments, which it then ignores (no run, nothing written) -- but
        # not after "--", where it is a file name.
        s = self.scene()
        for cmd in ("run", "check", "explain", "convert", "help"):
            want = self.rbsim("help", cmd)
            self.assertEqual(want.returncode, 0, cmd)
            self.assertIn("usage: rbsim " + cmd, want.stdout)
            for flag in ("--help", "-h"):
                r = self.rbsim(cmd, flag)
                self.assertEqual((r.returncode, r.stdout, r.stderr),
                                 (0, want.stdout, ""), (cmd, flag))
        r = self.rbsim("run", s, "--csv", "h.csv", "--help")
        self.assertEqual((r.returncode, r.stdout), (0, self.rbsim("help", "run").stdout))
        self.assertFalse(os.path.exists(self.path("h.csv")))
        r = self.rbsim("convert", s, "out.json", "-h")
        self.assertEqual((r.returncode, r.stdout),
                         (0, self.rbsim("help", "convert").stdout))
        self.assertFalse(os.path.exists(self.path("out.json")))
        r = self.rbsim("run", "--quiet", "--", "--help")
        self.assertEqual(r.returncode, 3, r.stderr)  # the scene file '--help'
        self.assertIn("--help", r.stderr)
        self.assertIn("also\n                         COMMAND --help",
                      self.rbsim("help").stdout)

    def test_usage_errors_write_nothing(self):
        s = self.scene()
        cases = [
            (["--steps", "abc"], "--steps"),
            (["--steps", "2^53+1"], "--steps: expected a whole number from 0 to 2^53"),
            (["--every", "2147483648"],
             "--every: expected a whole number from 1 to 2147483647 (2^31 - 1), "
             "got '2147483648'"),
            (["--steps=-3"], "--steps"),
            (["--dt", "-1"], "--dt"),
            (["--dt", "nan"], "--dt"),
            (["--dt", "0x10"], "--dt: expected a time step"),  # (strtod's hex)
            (["--dt", "1e-400"], "got '1e-400' (below the smallest double"),
            (["--dt", "1e400"], "got '1e400' (beyond the largest double"),
            (["--slop", " 0.01"], "--slop"),
            (["--method", "leapfrog"], "unknown method 'leapfrog'; expected euler, "
             "selective, event, verlet, rk4, adaptive, soft or auto"),
            (["--slop", "0.1"], "--slop: expected a fraction of the smaller radius in (0, 0.1)"),
            (["--slop", "0"], "--slop: expected"),
            (["--slop", "nan"], "--slop: expected"),
            (["--slop", "loose"], "--slop: expected"),
            (["--slop", "0.01", "--slop=0.02"], "--slop given twice"),
            (["--every", "0"], "--every"),
            (["--reel", "1"], "--reel"),
            (["--threads", "0"], "--threads: expected a whole number of threads "
             "from 1 to 16, got '0'"),
            (["--threads", "17"], "from 1 to 16, got '17'"),
            (["--threads", "two"], "--threads: expected"),
            (["--threads", "2", "--threads=3"], "--threads given twice"),
            (["--speed", "0"], "--speed"),
            (["--speed", "2"], "--speed sets the pace of --realtime"),
            # --every thins --csv, --json and --png only: alone, or with
            # --stats (every frame) alone, it changed nothing, silently
            (["--every", "5"], "--every K keeps every K-th frame of --csv, "
             "--json and --png, and this run has none of them"),
            (["--every", "5", "--stats", "out.csv"], "--every K keeps"),
            (["--frobnicate"], "unknown option '--frobnicate'"),
            (["--csv"], "--csv needs a value"),
            (["--csv", "out.csv", "--csv", "x.csv"], "--csv given twice"),
            (["--steps", "5", "--steps=6"], "--steps given twice"),
            (["--quiet=1"], "takes no value"),
            ([s], "one scene at most"),
            (["--csv", "out.csv", "--json", "./out.csv"], "both write"),
            (["--csv", "out.csv", "--json", "out.csv"], "both write 'out.csv'"),
            (["--csv", "out.csv", "--stats", s], "would overwrite the scene"),
            (["--csv", "out.csv", "--json", "no/such/dir/x.jsonl"],
             "does not exist"),
            (["--csv", "out.csv", "--stats", self.dir], "is a folder"),
        ]
        for extra, msg in cases:
            r = self.rbsim("run", s, *extra)
            self.assertEqual(r.returncode, 2, (extra, r.stderr))
            self.assertIn(msg, r.stderr, extra)
            self.assertFalse(os.path.exists(self.path("out.csv")), extra)

    def test_a_flag_given_twice_is_refused(self):
        # "--paused --paused" (and --quiet, --realtime) was taken while a
        # value option given twice was refused: every option once.
        s = self.scene()
        for flag in ("--paused", "--quiet", "--realtime"):
            r = self.rbsim("run", s, flag, "--csv", "out.csv", flag)
            self.assertEqual(r.returncode, 2, (flag, r.stderr))
            self.assertIn("rbsim run: %s given twice" % flag, r.stderr)
            self.assertFalse(os.path.exists(self.path("out.csv")), flag)
        self.assertIn("--paused --paused is refused",
                      " ".join(self.rbsim("help", "run").stdout.split()))

    def test_failed_step_says_the_time_in_its_shortest_form(self):
        # Contacts outgrow max_contacts (2) when three balls land at once:
        # exit 4, the step and its time as they read back (t = 0.1 s, not
        # %.17g's 0.10000000000000001), the frames before it written.
        bodies = [{"name": "floor", "type": "plane", "point": [0, 0, 0],
                   "normal": [0, 0, 1]}]
        bodies += [{"name": "b%d" % k, "type": "sphere", "radius": 0.1,
                    "mass": 1, "position": [0.3 * k, 0, 0.15]}
                   for k in range(3)]
        s = self.scene(simulation={"steps": 1000, "dt": 0.001,
                                   "method": "euler", "max_contacts": 2},
                       bodies=bodies)
        r = self.rbsim("run", s, "--csv", "f.csv", "--quiet")
        self.assertEqual(r.returncode, 4, r.stderr)
        m = re.search(r"step (\d+) \(t = ([^ ]+) s\) failed", r.stderr)
        self.assertIsNotNone(m, r.stderr)
        t = float(m.group(2))
        self.assertEqual(m.group(2), repr(t))
        self.assertEqual(t, (int(m.group(1)) - 1) * 0.001)

    def test_check_convert_explain_name_the_bad_argument(self):
        # They said "expected one scene file" / "expected IN and OUT" for
        # any bad argument; like run, they name it (exit 2, nothing written).
        s = self.scene()
        for args, msg in (
                (["check", s, "--bogus"], "rbsim check: unknown option '--bogus'"),
                (["check", "--quiet", s], "rbsim check: unknown option '--quiet'"),
                (["check", s, "--steps", "5"], "rbsim check: unknown option '--steps'"),
                (["check", s, "more.json"], "rbsim check: unexpected argument 'more.json'"),
                (["check", ""], "rbsim check: argument 1 is an empty string"),
                (["check"], "rbsim check: expected one scene file"),
                (["convert", "--force", s, "b.json"],
                 "rbsim convert: unknown option '--force'"),
                (["convert", s, "b.json", "c.json"],
                 "rbsim convert: unexpected argument 'c.json'"),
                (["convert", s], "rbsim convert: expected OUT after IN"),
                (["explain", s, "more.json"],
                 "rbsim explain: unexpected argument 'more.json'"),
                (["explain", s, "--steps", "5"],
                 "rbsim explain: unknown option '--steps'")):
            r = self.rbsim(*args)
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(msg, r.stderr, args)
            self.assertIn("usage: rbsim " + args[0], r.stderr, args)
        self.assertEqual(os.listdir(self.dir), ["scene.json"])
        # "--" ends the options: a scene whose name starts with '-'
        shutil.copy(s, self.path("-odd.json"))
        r = self.rbsim("check", "--", "-odd.json")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_arguments_echoed_safely(self):
        # An unknown option, command, method or value was repeated raw: an
        # ESC in it ("--bogus\x1b[2J") cleared the terminal that showed the
        # error.  Each control character, C1 control (U+009B), bidirectional
        # override (U+202E) and byte of invalid UTF-8 shows as one '?';
        # letters beyond ASCII stay.  Exit 2 as for any usage error.
        s = self.scene().encode()
        esc, c1, rlo, bad = b"\x1b", "\u009b".encode(), "\u202e".encode(), b"\xff"
        for args, want in (
                ([b"run", s, b"--bogus" + esc + b"[2J"], b"unknown option '--bogus?[2J'"),
                ([b"run", s, b"--method=" + c1 + b"2J"], b"unknown method '?2J'"),
                ([b"run", s, b"--dt", b"1" + rlo + bad], b"got '1??'"),
                ([b"run", s, b"--steps", "\u00fc".encode()], "got '\u00fc'".encode()),
                ([b"ru" + esc + b"n"], b"rbsim: unknown command 'ru?n'"),
                ([b"help", b"x" + esc], b"rbsim help: unknown command 'x?'"),
                ([b"check", s, b"x" + esc], b"unexpected argument 'x?'"),
                ([b"convert", b"--f" + esc, s, b"o.json"], b"unknown option '--f?'"),
                ([b"explain", s, b"--method", b"x" + esc], b"unknown method 'x?'"),
                ([b"explain", s, b"-" + rlo], b"unknown option '-?'"),
                ([b"run", s, b"--csv", b"--x" + esc], None)):
            r = subprocess.run([RBSIM.encode()] + args, capture_output=True,
                               cwd=self.dir, timeout=60,
                               stdin=subprocess.DEVNULL)
            if want is None:
                # (a value: a file of that name is written, as asked)
                self.assertEqual(r.returncode, 0, r.stderr)
                continue
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(want, r.stderr, args)
            for raw in (esc, c1, rlo, bad):
                self.assertNotIn(raw, r.stderr, args)

    def test_paths_echoed_safely(self):
        # A renderer's path from the scene ("no\u001b[7mdir/x/y.csv") was
        # repeated raw in "cannot create ...", by check and by run, and an
        # output, checkpoint or resumed path in the run's summary and the
        # command's other messages: each ESC now shows as '?' (exit 3 for
        # the scene's path, as before).
        esc = "\x1b"
        s = self.scene(renderers=[{"type": "csv", "path": "no%s[7mdir/x/y.csv" % esc}])
        for cmd in ("check", "run"):
            r = subprocess.run([RBSIM, cmd, s], capture_output=True, cwd=self.dir,
                               timeout=60, stdin=subprocess.DEVNULL)
            self.assertEqual(r.returncode, 3, (cmd, r.stderr))
            said = r.stdout + r.stderr
            self.assertIn(b"cannot create 'no?[7mdir/x/y.csv'", said, cmd)
            self.assertNotIn(esc.encode(), said, cmd)
        s = self.scene()
        os.mkdir(self.path("o"))
        r = subprocess.run([RBSIM, "run", s, "--csv", "o/a%s.csv" % esc, "--checkpoint",
                            "o/c%s" % esc], capture_output=True, cwd=self.dir,
                           timeout=60, stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(b"output: csv o/a?.csv", r.stdout + r.stderr)
        self.assertIn(b"checkpoint: o/c? at frame", r.stdout + r.stderr)
        self.assertNotIn(esc.encode(), r.stdout + r.stderr)
        self.assertTrue(os.path.exists(self.path("o/a%s.csv" % esc)))  # the file as named
        # the command line's paths in its other messages, e.g. two outputs
        # onto one file, a missing folder, a checkpoint that is a folder
        for args, want in ((["--csv", "o/b%s.csv" % esc, "--json", "./o/b%s.csv" % esc],
                            b"both write './o/b?.csv'"),
                           (["--csv", "x%s/y/z.csv" % esc], b"cannot create 'x?/y/z.csv'"),
                           (["--checkpoint", "o"], b"--checkpoint 'o'")):
            r = subprocess.run([RBSIM, "run", s] + args, capture_output=True,
                               cwd=self.dir, timeout=60, stdin=subprocess.DEVNULL)
            self.assertNotEqual(r.returncode, 0, args)
            self.assertIn(want, r.stderr, args)
            self.assertNotIn(esc.encode(), r.stderr, args)
        # the scene's own path on the standard output
        odd = self.path("s%s.json" % esc)
        shutil.copy(s, odd)
        for cmd, want in (("check", b"s?.json: ok"), ("explain", b"scene: s?.json"),
                          ("run", b"scene: s?.json")):
            r = subprocess.run([RBSIM, cmd, "s%s.json" % esc], capture_output=True,
                               cwd=self.dir, timeout=60, stdin=subprocess.DEVNULL)
            self.assertEqual(r.returncode, 0, (cmd, r.stderr))
            self.assertIn(want, r.stdout + r.stderr, cmd)
            self.assertNotIn(esc.encode(), r.stdout + r.stderr, cmd)
        os.remove(odd)
        r = subprocess.run([RBSIM, "run", s, "--resume", "o/c%s" % esc, "--steps", "400"],
                           capture_output=True, cwd=self.dir, timeout=60,
                           stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(b"resumed: o/c? at frame", r.stdout + r.stderr)
        self.assertNotIn(esc.encode(), r.stdout + r.stderr)

    def test_long_paths_keep_the_reason(self):
        # A path past PATH_MAX was echoed whole into a 512-byte message, cut
        # off mid-path with no reason.  The path is shown shortened (its
        # start and end around "...") and the reason is said.
        s = self.scene()
        long = "a/" * 2100 + "x.csv"
        for opt in ("--csv", "--json", "--stats"):
            r = self.rbsim("run", s, opt, long)
            self.assertEqual(r.returncode, 2, (opt, r.stderr))
            self.assertIn("path too long: 4205 bytes, past the system's limit",
                          r.stderr)
            self.assertRegex(r.stderr, r"'a/a/[a/]*\.\.\.[a/]*/x\.csv': path too long")
            self.assertLess(len(r.stderr), 400)
        self.scene("long.json", renderers=[{"type": "csv", "path": long}])
        r = self.rbsim("check", "long.json")
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertIn("renderers[0] (csv): 'a/a/", r.stdout)
        self.assertIn("path too long", r.stdout)
        # a name past the file system's limit: its own reason
        r = self.rbsim("run", s, "--csv", "b" * 300 + "/x.csv")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertRegex(r.stderr, r"'b+\.\.\.b+/x\.csv': File name too long")
        self.assertEqual(os.listdir(self.dir), ["scene.json", "long.json"])

    def test_subnormal_dt_and_slop_are_numbers(self):
        # 5e-324 and 1e-310 are doubles > 0, as a scene's JSON takes them
        # (strtod's ERANGE for a subnormal result refused them).
        s = self.scene()
        for extra in (["--dt", "5e-324"], ["--dt", "1e-310"],
                      ["--slop", "1e-310"]):
            r = self.rbsim("run", s, "--steps", "2", "--quiet", *extra)
            self.assertEqual(r.returncode, 0, (extra, r.stderr))

    def test_a_material_on_no_body_is_a_warning(self):
        # A row naming a material no body has ("stel", a typo of "steel")
        # applies to no contact, and the "*" row took the ball's contacts:
        # `check` said "ok" (a probe of session 50).  Now check (stdout),
        # run, explain and convert (stderr) print the library's warning at
        # the row, as "FILE:LINE:COLUMN: PATH: warning: MESSAGE", and the
        # scene still loads and runs (exit 0, as scenes/FORMAT.md has it);
        # a text scene's warning names its materials.txt line.
        mats = [{"pair": ["steel", "*"], "static": 0.9, "kinetic": 0.8},
                {"pair": ["stel", "*"], "static": 0.1, "kinetic": 0.1},
                {"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3}]
        bodies = json.loads(json.dumps(SCENE["bodies"]))
        bodies[1]["material"] = "steel"
        p = self.scene(materials=mats, bodies=bodies)
        with open(p) as f:
            lines = f.read().split("\n")
        line = next(i for i, t in enumerate(lines) if '"stel"' in t) + 1
        column = lines[line - 1].index('"stel"') + 1
        want = ("scene.json:%d:%d: materials[1].pair[0]: warning: material \"stel\" is on no "
                "body, so this row applies to no contact (did you mean \"steel\"?)\n"
                % (line, column))
        r = self.rbsim("check", "scene.json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, want + "scene.json: ok (300 steps, 0 renderers)\n")
        r = self.rbsim("run", "scene.json", "--steps", "2", "--quiet")
        self.assertEqual((r.returncode, r.stderr), (0, want))
        r = self.rbsim("explain", "scene.json")
        self.assertEqual((r.returncode, r.stderr), (0, want))
        self.assertNotIn("warning", r.stdout)
        r = self.rbsim("convert", "scene.json", "t/config.txt")
        self.assertEqual((r.returncode, r.stderr), (0, want))
        r = self.rbsim("check", "t/config.txt")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("t/materials.txt:3:1: materials[1].pair[0]: warning: material \"stel\"",
                      r.stdout)
        # every material on a body: nothing to say
        r = self.rbsim("check", self.scene("fine.json"))
        self.assertEqual(r.stdout, "%s: ok (300 steps, 0 renderers)\n" % self.path("fine.json"))

    def test_check_refuses_what_run_refuses(self):
        # The scene's own renderer entries: two names for one file, or an
        # output onto the scene itself, are refused by `check` as by `run`
        # (exit 3 both; the probe of session 38 found check passing a scene
        # whose two outputs were "out/same.csv" and "out/../out/same.csv").
        # Each is said at the entry's place and key path (FORMAT.md's
        # "FILE:LINE:COLUMN: KEY.PATH: ..."; it was "rbsim check: ..."), and
        # two spellings of one path as written ("a.csv", "./a.csv") are the
        # library's own error, at the path itself.
        os.mkdir(self.path("out"))
        for rs, msg, where in (
                ([{"type": "csv", "path": "out/same.csv"},
                  {"type": "json", "path": "out/../out/same.csv"}],
                 "both write 'out/../out/same.csv'", (1, "{")),
                ([{"type": "csv", "path": "./scene.json"}],
                 "would overwrite the scene", (0, "{")),
                ([{"type": "csv", "path": "out/a.csv"},
                  {"type": "json", "path": "./out/a.csv"}],
                 "renderers[0] already writes \"out/a.csv\", the file "
                 "\"./out/a.csv\" names", (1, '"./out/a.csv"'))):
            s = self.scene(renderers=rs)
            with open(s) as f:
                text = f.read()
            at = text.index('"renderers"')
            for _ in range(where[0] + 1):
                at = text.index('{', at + 1)
            if where[1] != "{":
                at = text.index(where[1], at)
            head = text[:at]
            place = "scene.json:%d:%d: renderers[%d].path: " % (
                head.count("\n") + 1, at - head.rfind("\n"), where[0])
            r = self.rbsim("check", "scene.json")
            self.assertEqual(r.returncode, 3, (rs, r.stdout, r.stderr))
            self.assertIn(place, r.stdout + r.stderr)
            self.assertIn(msg, r.stdout + r.stderr)
            r = self.rbsim("run", "scene.json")
            self.assertEqual(r.returncode, 3, (rs, r.stderr))
            self.assertIn(place, r.stdout + r.stderr)
            self.assertIn(msg, r.stdout + r.stderr)
            self.assertEqual(os.listdir(self.path("out")), [])
        # distinct files pass both
        s = self.scene(renderers=[{"type": "csv", "path": "out/a.csv"},
                                  {"type": "json", "path": "out/../out/b.jsonl"}])
        r = self.rbsim("check", s)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)

    def test_no_output_overwrites_a_text_scenes_files(self):
        # A text scene is read from three files: an output (or the
        # checkpoint) onto its materials.txt or objects.txt was written over
        # it (exit 0, objects.txt held the stats CSV); only config.txt was
        # refused.  Now each is refused before the run (exit 2, a scene
        # entry exit 3, `check` alike) and nothing is written.
        s = self.scene()
        self.assertEqual(self.rbsim("convert", s, "t/config.txt").returncode, 0)
        files = ("config.txt", "materials.txt", "objects.txt")

        def texts():
            out = {}
            for n in files:
                with open(self.path("t/" + n)) as f:
                    out[n] = f.read()
            return out
        before = texts()
        for scene in ("t/config.txt", "t"):
            for name in files:
                for opt in ("--csv", "--json", "--stats", "--checkpoint"):
                    r = self.rbsim("run", scene, opt, "t/" + name, "--quiet")
                    self.assertEqual(r.returncode, 2, (scene, opt, name, r.stderr))
                    self.assertIn("'t/%s' would overwrite the scene" % name,
                                  r.stderr)
                    if name != "config.txt":
                        self.assertIn("the scene's file 't/%s'" % name, r.stderr)
        self.assertEqual(texts(), before)
        with open(self.path("t/config.txt"), "a") as f:
            f.write("renderer = csv path=t/objects.txt\n")
        before = texts()
        for cmd in ("check", "run"):
            r = self.rbsim(cmd, "t/config.txt")
            self.assertEqual(r.returncode, 3, (cmd, r.stdout + r.stderr))
            self.assertIn("renderers[0].path: the csv output 't/objects.txt' "
                          "would overwrite the scene's file 't/objects.txt'",
                          r.stdout + r.stderr)
        self.assertEqual(texts(), before)
        self.assertEqual(sorted(os.listdir(self.path("t"))), sorted(files))

    def test_soft_method(self):
        """--method soft runs a scene (frames 0..50, the method reported
        in explain); the scene's simulation.soft_substeps reaches the
        world, and a checkpoint made with one soft_substeps does not resume
        with another."""
        s = self.scene()
        r = self.rbsim("run", s, "--method", "soft", "--steps", "50", "--quiet",
                       "--csv", "soft.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("soft.csv")), 51)
        r = self.rbsim("explain", s, "--method", "soft")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("method: soft", r.stdout)
        self.setting_binds_checkpoint("soft_substeps", 8, 4, 1001,
                                      "must be an integer from 1 to 1000, got 1001")

    def test_threads_same_bytes(self):
        """--threads N lends the world N - 1 threads of a pool: a pile of
        640 spheres (enough for the soft step's slabs to split among them)
        gives the same CSV bytes on 1, 2 and 3 threads -- the library's
        promise, checked here through the command line."""
        bodies = [{"name": "floor", "type": "plane", "point": [0, 0, 0],
                   "normal": [0, 0, 1]}]
        for k in range(640):
            i, j, l = k % 8, (k // 8) % 8, k // 64
            bodies.append({"name": "s%03d" % k, "type": "sphere",
                           "radius": 0.05, "mass": 0.1,
                           "position": [0.11 * i + 0.002 * (l % 3),
                                        0.11 * j, 0.06 + 0.11 * l]})
        s = self.scene("pile.json", bodies=bodies,
                       simulation={"steps": 120, "dt": 0.001,
                                   "method": "soft"})
        sums = []
        for t in ("1", "2", "3"):
            out = "pile_%s.csv" % t
            r = self.rbsim("run", s, "--threads", t, "--quiet", "--csv", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(self.path(out), "rb") as f:
                sums.append(f.read())
        self.assertGreater(len(sums[0]), 640 * 121 * 50)  # every frame, whole
        self.assertEqual(sums[0], sums[1])
        self.assertEqual(sums[0], sums[2])
        self.assertIn("--threads N", self.rbsim("help", "run").stdout)

    def test_soft_tolerance(self):
        """The scene's simulation.soft_tolerance reaches the world (as
        soft_substeps does, above); out of [0, 1] the scene is rejected."""
        self.setting_binds_checkpoint("soft_tolerance", 0.25, 0, 2,
                                      "must be in [0, 1], got 2")

    def test_work_cap_is_reported(self):
        """A step past its work cap (simulation.max_substeps) takes the
        rest of its frame without rollback: in the 1e6:1 pi billiard at
        dt = 1 ms the light ball then passed through the heavy one, and the
        summary looked clean.  Now the summary says how many steps hit the
        cap and what it means, the stats have a work_limit column, and the
        scene's max_substeps raises the cap (3141 impacts, exact)."""
        bodies = [
            {"name": "wall", "type": "plane", "point": [0, 0, 0], "normal": [1, 0, 0]},
            {"name": "light", "type": "sphere", "radius": 0.1, "mass": 1,
             "position": [0.5, 0, 0]},
            {"name": "heavy", "type": "sphere", "radius": 0.1, "mass": 1e6,
             "position": [1, 0, 0], "velocity": [-1, 0, 0]}]
        sim = {"steps": 2000, "dt": 0.001, "gravity": [0, 0, 0], "restitution": 1,
               "method": "euler"}
        mats = [{"pair": ["*", "*"], "static": 0, "kinetic": 0, "restitution": 1}]
        s = self.scene("pi.json", bodies=bodies, simulation=sim, materials=mats)
        r = self.rbsim("run", s, "--stats", "pi.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.path("pi.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        capped = sum(int(x["work_limit"]) for x in rows)
        self.assertGreater(capped, 0)
        self.assertIn("work cap: %d of 2000 steps hit max_substeps = 4096" % capped, r.stdout)
        self.assertIn("impacts there may be missed or wrong", r.stdout)
        s = self.scene("pi2.json", bodies=bodies, materials=mats,
                       simulation=dict(sim, max_substeps=20000))
        r = self.rbsim("run", s, "--stats", "pi2.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("work cap", r.stdout)
        self.assertIn("3141 collisions", r.stdout)
        self.setting_binds_checkpoint("max_substeps", 512, 4096, 0,
                                      "must be an integer from 1 to 4294967295 (2^32 - 1), "
                                      "got 0")

    def test_jam_and_sweep_limit_are_reported(self):
        """A ball at 1000 m/s between two walls 20 um wider than it takes
        ~5,000 impacts a step; selective stops a body at 2,000 a step
        (100 x max_sweeps) and pushes what is left apart.  Only the C and
        Python step reports said so: the run's summary looked clean (a
        probe of session 43).  Now it counts the steps with overlap pushed
        apart and those with a pass at max_sweeps; a quiet run says
        neither."""
        bodies = [
            {"name": "b", "type": "sphere", "radius": 0.1, "mass": 1,
             "position": [0, 0, 0], "velocity": [1000, 0, 0]},
            {"name": "l", "type": "plane", "point": [-0.10001, 0, 0], "normal": [1, 0, 0]},
            {"name": "r", "type": "plane", "point": [0.10001, 0, 0], "normal": [-1, 0, 0]}]
        sim = {"steps": 20, "dt": 0.001, "gravity": [0, 0, 0], "restitution": 1,
               "method": "selective"}
        mats = [{"pair": ["*", "*"], "static": 0, "kinetic": 0, "restitution": 1}]
        s = self.scene("walls.json", bodies=bodies, simulation=sim, materials=mats)
        r = self.rbsim("run", s)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("overlap: 20 of 20 steps pushed overlap apart instead of resolving it",
                      r.stdout)
        self.assertIn("sweeps: 20 of 20 steps had a contact pass stop at max_sweeps", r.stdout)
        s = self.scene("walls2.json", bodies=[dict(bodies[0], velocity=[1, 0, 0])] + bodies[1:],
                       simulation=sim, materials=mats)
        r = self.rbsim("run", s)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("overlap:", r.stdout)
        self.assertNotIn("sweeps:", r.stdout)

    def test_deep_sink_and_lost_motion_are_reported(self):
        """The soft step sinks a load by load / (m_eff omega^2): a ball at
        rest on a floor under g = 1e8 m/s^2 (dt = 1 ms) ended 2.4 m, 25
        radii, under it, and the summary said nothing but the energy's
        drift; a ball at 0.05 m/s 1e12 m from the origin did not move, and
        nothing said so (a probe of session 45).  Now the summary names the
        deepest overlap beyond 1 % of the smallest radius, and the steps
        whose slow motion rounding lost; at g = 9.81 and at the origin
        neither line."""
        sim = {"steps": 200, "dt": 0.001, "gravity": [0, 0, -1e8], "method": "soft"}
        mats = [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.5, "restitution": 0}]
        ball = {"name": "b", "type": "sphere", "radius": 0.1, "mass": 1, "position": [0, 0, 0.1]}
        floor = {"name": "f", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]}
        r = self.rbsim("run", self.scene("sink.json", bodies=[ball, floor], simulation=sim,
                                         materials=mats))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("overlap: the deepest at a step's end was", r.stdout)
        self.assertIn("of the smallest radius (0.1 m)", r.stdout)
        r = self.rbsim("run", self.scene("rest.json", bodies=[ball, floor],
                                         simulation=dict(sim, gravity=[0, 0, -9.81]),
                                         materials=mats))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("overlap:", r.stdout)
        self.assertNotIn("rounding:", r.stdout)
        far = dict(ball, position=[1e12, 0, 0], velocity=[0.05, 0, 0])
        r = self.rbsim("run", self.scene("far.json", bodies=[far],
                                         simulation=dict(sim, gravity=[0, 0, 0], method="euler")))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("rounding: 200 of 200 steps moved a sphere by less than a thousandth",
                      r.stdout)

    def setting_binds_checkpoint(self, key, made, other, bad, message):
        """A soft scene's simulation.KEY reaches the world: a checkpoint
        made with KEY = made does not resume with KEY = other, and resumes
        with made; KEY = bad is rejected by check with the message."""
        sim = dict(SCENE["simulation"], method="soft", **{key: made})
        s = self.scene(f"{key}_made.json", simulation=sim)
        r = self.rbsim("run", s, "--steps", "20", "--quiet", "--checkpoint", f"{key}.ckpt")
        self.assertEqual(r.returncode, 0, r.stderr)
        s2 = self.scene(f"{key}_other.json", simulation=dict(sim, **{key: other}))
        r = self.rbsim("run", s2, "--resume", f"{key}.ckpt", "--quiet", "--csv", f"{key}2.csv")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn(f"{key}: the scene has {other}, the checkpoint {made}", r.stderr)
        r = self.rbsim("run", s, "--steps", "40", "--resume", f"{key}.ckpt", "--quiet",
                       "--csv", f"{key}3.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        b = self.scene(f"{key}_bad.json", simulation=dict(sim, **{key: bad}))
        r = self.rbsim("check", b)
        self.assertEqual(r.returncode, 3)
        self.assertIn(f"simulation.{key}: {message}", r.stdout)

    def test_help_lists_every_method(self):
        """The unknown-method messages of run and explain name the
        library's methods (rbs_method_name); the help of run and explain
        lists each of them."""
        s = self.scene()
        r = self.rbsim("run", s, "--method", "leapfrog")
        self.assertEqual(r.returncode, 2)
        tail = r.stderr.split("expected ", 1)[1].splitlines()[0]
        names = tail.replace(" or ", ", ").split(", ")
        self.assertEqual(names, ["euler", "selective", "event", "verlet", "rk4",
                                 "adaptive", "soft", "auto"])
        r = self.rbsim("explain", s, "--method", "leapfrog")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--method: unknown method 'leapfrog'; expected " + tail, r.stderr)
        for command in ("run", "explain"):
            text = " ".join(self.rbsim("help", command).stdout.split())
            for name in names:
                self.assertRegex(text, r"--method M.*\b%s\b" % name, (command, name))

    def test_slop_option(self):
        """--slop overrides simulation.slop: a ball of r = 0.1 m dropped
        0.1 m (impact at 1.4 m/s, at most 1.42 mm a step) is rolled back at
        its impact with the default slop (1e-6 r) and never with 0.02
        (2 mm), whose overlap stays within 2 mm; a checkpoint made with one
        slop does not resume with another."""
        s = self.scene(bodies=[SCENE["bodies"][0],
                               {"name": "ball", "type": "sphere", "radius": 0.1,
                                "mass": 1, "position": [0, 0, 0.2]}])
        rolled = {}
        for slop in (None, "0.02"):
            extra = [] if slop is None else ["--slop", slop]
            st = "st_%s.csv" % slop
            r = self.rbsim("run", s, "--stats", st, "--quiet", "--csv", "x_%s.csv" % slop, *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(self.path(st), newline="") as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), 301)
            rolled[slop] = sum(int(x["rollbacks"]) for x in rows)
            worst = max(float(x["max_overlap"]) for x in rows)
            self.assertLessEqual(worst, (0.02 if slop else 1e-6) * 0.1)
        self.assertGreater(rolled[None], 0)
        self.assertEqual(rolled["0.02"], 0)
        r = self.rbsim("run", s, "--steps", "100", "--checkpoint", "c.ckpt", "--quiet",
                       "--csv", "c1.csv", "--slop", "0.02")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--resume", "c.ckpt", "--quiet", "--csv", "c2.csv")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("slop", r.stderr)

    def test_too_many_outputs(self):
        s = self.scene(renderers=[{"type": "csv", "path": "s1.csv"},
                                  {"type": "json", "path": "s2.jsonl"}])
        r = self.rbsim("run", s, "--csv", "a.csv", "--json", "b.jsonl",
                       "--stats", "c.csv")
        self.assertEqual(r.returncode, 2)
        self.assertIn("at most 4 renderers", r.stderr)
        self.assertEqual(sorted(os.listdir(self.dir)), ["scene.json"])

    def test_unknown_renderer_type_is_named_with_a_suggestion(self):
        # A misspelt type got "(known: csv, json, stats, sdl)" and no
        # "did you mean", which a misspelt key or method gets; check said
        # "renderers[0].type:", run "renderers[0]:".  Now one form for both:
        # the key path, the closest known type, and what sdl writes (a
        # user asking for "png").
        cases = [("cvs", 'renderers[0].type: unknown renderer type "cvs" '
                         '(did you mean "csv"?; known: csv, json, stats'),
                 ("jsonl", '(did you mean "json"?; known:'),
                 ("png", 'renderers[0].type: unknown renderer type "png" '
                         '(known: csv, json, stats')]
        for typ, msg in cases:
            s = self.scene(renderers=[{"type": typ, "path": "o.csv"}])
            r = self.rbsim("check", s)
            self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
            self.assertIn("scene.json:", r.stdout)
            self.assertIn(msg, r.stdout)
            r = self.rbsim("run", s, "--quiet")
            self.assertEqual(r.returncode, 3, r.stderr)
            self.assertIn(msg, r.stderr)
            self.assertFalse(os.path.exists(self.path("o.csv")))
        if "sdl" in self.rbsim("check", s).stdout:  # (built with SDL)
            self.assertIn("sdl (PNG frames)", r.stderr)
            self.assertNotIn("did you mean", r.stderr)

    def test_a_misspelt_scene_path_gets_a_suggestion(self):
        # "rbsim run scene.jsn" said only "No such file or directory"; a
        # misspelt key or type gets "did you mean", so does a misspelt file:
        # the closest name (at most 2 edits) in the folder it names.
        self.scene("scene.json")
        for cmd, out in (("check", "stdout"), ("explain", "stdout"),
                         ("run", "stderr"), ("convert", "stderr")):
            args = [cmd, self.path("scnee.json")] + (["o.json"] if cmd == "convert" else [])
            r = self.rbsim(*args)
            self.assertEqual(r.returncode, 3, (cmd, r.stdout, r.stderr))
            text = getattr(r, out)
            self.assertIn("No such file or directory", text, cmd)
            self.assertIn("did you mean '%s'?" % self.path("scene.json"), text, cmd)
        r = self.rbsim("check", "scnee.json")  # (relative: as given)
        self.assertIn("did you mean 'scene.json'?", r.stdout)
        r = self.rbsim("check", self.path("far_from_anything.json"))
        self.assertEqual(r.returncode, 3)
        self.assertNotIn("did you mean", r.stdout)

    def test_a_file_read_as_a_text_scene_by_its_name_says_so(self):
        # "rbsim check README.md" gave 50 lines of 'expected "key = value"'
        # and "... and N more errors", never saying why a Markdown file was
        # read as a config.txt.  A note after the errors says so; not for a
        # .txt file or a JSON one.
        note = ("was read as a text scene's config.txt: its name does not "
                "end in .json and it does not start with '{'")
        with open(self.path("notes.md"), "w") as f:
            f.write("# Notes\n\nA scene, some day.\n")
        with open(self.path("config.txt"), "w") as f:
            f.write("stpes = 3\n")
        with open(self.path("bad.json"), "w") as f:
            f.write("{\"simulation\": 1}\n")
        for cmd, out in (("check", "stdout"), ("run", "stderr")):
            r = self.rbsim(cmd, "notes.md")
            self.assertEqual(r.returncode, 3, (cmd, r.stdout, r.stderr))
            self.assertIn("notes.md " + note, getattr(r, out), cmd)
            for other in ("config.txt", "bad.json"):
                r = self.rbsim(cmd, other)
                self.assertEqual(r.returncode, 3, (cmd, other))
                self.assertNotIn("was read as", r.stdout + r.stderr, (cmd, other))

    def test_scene_errors(self):
        bad = self.scene(bodies=[{"name": "x", "type": "sphere",
                                  "radius": -1, "mass": 1,
                                  "position": [0, 0, 1]},
                                 {"name": "y", "type": "cube"}])
        r = self.rbsim("check", bad)
        self.assertEqual(r.returncode, 3)
        lines = [l for l in r.stdout.splitlines() if l]
        self.assertGreaterEqual(len(lines), 2, r.stdout)  # every error
        self.assertIn("scene.json:", r.stdout)
        self.assertIn("radius", r.stdout)
        self.assertIn("cube", r.stdout)
        r = self.rbsim("run", bad, "--csv", "out.csv")
        self.assertEqual(r.returncode, 3)
        self.assertFalse(os.path.exists(self.path("out.csv")))
        r = self.rbsim("check", self.path("missing.json"))
        self.assertEqual(r.returncode, 3)
        r = self.rbsim("run", self.path("missing.json"))
        self.assertEqual(r.returncode, 3)
        good = self.scene("good.json")
        r = self.rbsim("check", good)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("ok", r.stdout)
        self.assertEqual(self.rbsim("check").returncode, 2)

    def test_one_missing_output_folder_is_created(self):
        # the demonstration scenes write to out/NAME.csv: one missing folder
        # (whose parent exists) is created when the run starts
        s = self.scene(renderers=[{"type": "csv", "path": "made/x.csv"}])
        r = self.rbsim("run", s)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.isfile(self.path("made/x.csv")))

    def test_scene_output_rejected_writes_nothing(self):
        # two missing folders are more likely a typo: refused, nothing written
        s = self.scene(renderers=[{"type": "csv", "path": "good.csv"},
                                  {"type": "json",
                                   "path": "nowhere/deeper/x.jsonl"}])
        r = self.rbsim("run", s)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("nowhere", r.stderr)
        self.assertIn("scene.json:", r.stderr)
        self.assertFalse(os.path.exists(self.path("good.csv")))
        r = self.rbsim("check", s)
        self.assertEqual(r.returncode, 3)
        self.assertIn("nowhere", r.stdout)

    def test_output_under_a_file_is_refused_by_check(self):
        # "rbsim check" passed a renderer path whose folder is a file
        # ("base.json/x.jsonl", "/dev/null/x.csv": taken for one missing
        # folder, its grandparent checked) or a folder where nothing can be
        # made (/proc, where root passes access()), which "rbsim run" then
        # refused (exit 3, "Not a directory").  Both refuse it now, naming
        # the entry and the part that is not a folder.
        with open(self.path("base.json"), "w") as f:
            f.write("{}")
        for path, msg in (("base.json/x.jsonl", "'base.json' is not a folder"),
                          ("base.json/a/x.jsonl", "'base.json' is not a folder"),
                          ("/dev/null/x.csv", "'/dev/null' is not a folder"),
                          ("/proc/x.csv", "cannot create '/proc/x.csv' in '/proc'")):
            s = self.scene(renderers=[{"type": "stats", "path": "ok.csv"},
                                      {"type": "json", "path": path}])
            r = self.rbsim("check", s)
            self.assertEqual(r.returncode, 3, (path, r.stdout))
            self.assertIn("renderers[1] (json): cannot create '%s'" % path,
                          r.stdout)
            self.assertIn(msg, r.stdout)
            r = self.rbsim("run", s)
            self.assertEqual(r.returncode, 3, (path, r.stderr))
            self.assertIn(msg, r.stderr)
            self.assertFalse(os.path.exists(self.path("ok.csv")))
            r = self.rbsim("run", self.scene(), "--csv", path)
            self.assertEqual(r.returncode, 2, (path, r.stderr))
            self.assertIn("--csv: cannot create '%s'" % path, r.stderr)
            self.assertIn(msg, r.stderr)

    def test_scene_renderers_and_every(self):
        s = self.scene(renderers=[{"type": "csv", "path": "all.csv"},
                                  {"type": "csv", "path": "some.csv",
                                   "every": 7}])
        r = self.rbsim("run", s, "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, "")  # --quiet
        self.assertEqual(self.assert_whole_frames(self.path("all.csv")), 301)
        rows = self.read_csv(self.path("some.csv"))
        frames = sorted({int(x[0]) for x in rows})
        self.assertEqual(frames, [k for k in range(301) if k % 7 == 0 or
                                  k == 300])
        # The kept frames are the same rows as in the full file.
        full = {(x[0], x[2]): x for x in self.read_csv(self.path("all.csv"))}
        for x in rows:
            self.assertEqual(full[(x[0], x[2])], x)

    def test_csv_bit_exact(self):
        out = self.path("truth.csv")
        r = subprocess.run([CSV_TRUTH, out, "250"], capture_output=True,
                           text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        truth = [l.split() for l in r.stdout.splitlines()]
        rows = self.read_csv(out)
        # (what csv_truth names its bodies; "+plain", a formula to a
        # spreadsheet, is written marked as text: see the next test)
        names = ["tilted_floor", "'+plain", "semi;colon", "single'quote",
                 "'@both'x"]
        self.assertEqual(len(rows), len(truth))
        self.assertEqual(len(rows), 251 * 5)
        for row, t in zip(rows, truth):
            self.assertEqual(row[0], t[0])
            self.assertEqual(bits(float(row[1])), bits(float.fromhex(t[1])))
            self.assertEqual(row[2], t[2])
            self.assertEqual(row[3], names[int(t[2])])
            for a, b in zip(row[4:], t[3:]):
                self.assertEqual(bits(float(a)), bits(float.fromhex(b)),
                                 (row, t))
        # Shortest form: no number has more digits than it needs.
        for row in rows[:500]:
            for a in row[4:]:
                x = float(a)
                mantissa = a.lstrip("-").split("e")[0]
                digits = mantissa.replace(".", "").strip("0")
                if len(digits) > 1:
                    shorter = "%.*g" % (len(digits) - 1, x)
                    self.assertNotEqual(float(shorter), x, a)

    def test_stdout_by_its_file_name_is_stdout(self):
        # /dev/stdout (or the file stdout is redirected to) is written as
        # "-": into the stream as it is, appended after what it held, and
        # one output at most.
        s = self.scene()
        r = self.rbsim("run", s, "--quiet", "--steps", "2", "--csv",
                       "/dev/stdout", "--json", "-")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("both write to standard output", r.stderr)
        out = self.path("o.txt")
        with open(out, "w") as f:
            f.write("PRIOR\n")
        with open(out, "a") as f:
            r = subprocess.run([RBSIM, "run", s, "--quiet", "--steps", "1",
                                "--csv", "/dev/stdout"], stdout=f,
                               stderr=subprocess.PIPE, text=True,
                               cwd=self.dir, timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(out) as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[0], "PRIOR")
        self.assertEqual(",".join(lines[1:2]), CSV_HEADER)
        self.assertEqual(len(lines), 2 + 2 * len(SCENE["bodies"]))
        # into a pipe (capture_output): the CSV comes through
        r = self.rbsim("run", s, "--quiet", "--steps", "1", "--csv",
                       "/dev/stdout")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.splitlines()[0], CSV_HEADER)

    def test_two_outputs_through_a_link_to_a_new_file(self):
        # link.csv -> o11.csv, which does not exist yet: one file, refused
        # before anything is written (it was written twice, one lost).
        s = self.scene("l.json", renderers=[{"type": "csv", "path": "o11.csv"}])
        os.symlink("o11.csv", self.path("link.csv"))
        r = self.rbsim("run", s, "--steps", "1", "--json", "link.csv",
                       "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("both write 'link.csv'", r.stderr)
        self.assertFalse(os.path.exists(self.path("o11.csv")))

    def test_whole_numbers_are_written_as_whole_numbers(self):
        # A frame's time of 10 s is "10", not the shorter "1e+01"; -0 keeps
        # its sign; whole numbers from 2^53 on keep the shortest form.
        s = self.scene(simulation=dict(SCENE["simulation"], dt=0.5, steps=40))
        r = self.rbsim("run", s, "--csv", "w.csv", "--json", "w.jsonl",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        times = sorted({row[1] for row in self.read_csv(self.path("w.csv"))},
                       key=float)
        self.assertEqual(times[:4], ["0", "0.5", "1", "1.5"])
        self.assertEqual(times[-1], "20")
        self.assertIn("10", times)
        self.assertFalse([t for t in times if "e" in t], times)
        with open(self.path("w.jsonl")) as f:
            last = json.loads(f.read().splitlines()[-1])
        self.assertEqual(last["t"], 20)

    def test_csv_names_are_never_formulas(self):
        # A name a spreadsheet would evaluate (leading = + - @, tab, CR) is
        # written with an apostrophe in front, and so is a name beginning
        # with one; every other name is written as it is.  Dropping one
        # leading apostrophe gives every name back.
        # (names allow no '=', ',', blank or control character, in scene
        # files and through the C API alike)
        names = ["+cmd|'/C_calc'!A0", "-1+2", "@SUM(1+1)", "'quoted", "plain",
                 "mid-dle+x"]
        bodies = [{"name": n, "type": "sphere", "radius": 0.1, "mass": 1,
                   "position": [3.0 * i, 0, 5]} for i, n in enumerate(names)]
        s = self.scene("names.json", bodies=bodies)
        r = self.rbsim("run", s, "--csv", "n.csv", "--steps", "1")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = self.read_csv(self.path("n.csv"))
        written = [row[3] for row in rows if row[0] == "0"]
        self.assertEqual(written, ["'+cmd|'/C_calc'!A0", "'-1+2", "'@SUM(1+1)",
                                   "''quoted", "plain", "mid-dle+x"])
        self.assertEqual([w[1:] if w.startswith("'") else w for w in written],
                         names)

    def test_negative_zero_keeps_its_sign(self):
        # -0.0 in: "-0" in CSV, "-0.0" in JSON (json.loads maps "-0" to the
        # integer 0, whose sign is gone); both read back as -0.0
        bodies = [{"name": "ball", "type": "sphere", "radius": 0.1, "mass": 1,
                   "position": [-0.0, 0, 5]}]
        s = self.scene("negz.json", bodies=bodies)
        r = self.rbsim("run", s, "--csv", "z.csv", "--json", "z.jsonl",
                       "--steps", "1")
        self.assertEqual(r.returncode, 0, r.stderr)
        x_csv = float(self.read_csv(self.path("z.csv"))[0][4])
        with open(self.path("z.jsonl")) as f:
            x_json = json.loads(f.readline())["bodies"][0]["position"][0]
        self.assertIsInstance(x_json, float)
        self.assertEqual(math.copysign(1.0, x_csv), -1.0)
        self.assertEqual(math.copysign(1.0, x_json), -1.0)

    def test_json_lines_valid_and_equal_to_csv(self):
        s = self.scene()
        r = self.rbsim("run", s, "--csv", "a.csv", "--json", "a.jsonl",
                       "--stats", "st.csv", "--steps", "200")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = self.read_csv(self.path("a.csv"))
        with open(self.path("a.jsonl")) as f:
            lines = f.read().split("\n")
        self.assertEqual(lines[-1], "")
        objs = [json.loads(l) for l in lines[:-1]]  # every line valid
        self.assertEqual([o["frame"] for o in objs], list(range(201)))
        i = 0
        for o in objs:
            self.assertEqual(len(o["bodies"]), BODIES)
            for b in o["bodies"]:
                row = rows[i]
                i += 1
                self.assertEqual(int(row[0]), o["frame"])
                self.assertEqual(bits(float(row[1])), bits(o["t"]))
                self.assertEqual(row[3], b["name"])
                vals = (b["position"] + b["orientation"] + b["velocity"] +
                        b["angular_velocity"])
                for a, v in zip(row[4:], vals):
                    self.assertEqual(bits(float(a)), bits(float(v)))
        with open(self.path("st.csv"), newline="") as f:
            st = list(csv.reader(f))
        self.assertEqual(",".join(st[0]), STATS_HEADER)
        self.assertEqual([int(x[0]) for x in st[1:]], list(range(201)))
        for x in st[1:]:
            self.assertEqual(len(x), 17)
            # total = kinetic + potential, as the world computed it (to
            # rounding of the sum: 1 ulp of the larger part, times 4).
            k, p, t = float(x[2]), float(x[3]), float(x[4])
            self.assertLessEqual(abs(k + p - t),
                                 4 * math.ulp(max(abs(k), abs(p), 1e-300)))

    def test_stdout_output_and_zero_steps(self):
        # "-" writes to stdout; the summary then goes to stderr.
        sim = dict(SCENE["simulation"], steps=0)
        s = self.scene(simulation=sim)
        r = self.rbsim("run", s, "--json", "-")
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertEqual(len(lines), 1)  # frame 0 only
        self.assertEqual(json.loads(lines[0])["frame"], 0)
        self.assertEqual(json.loads(lines[0])["t"], 0)
        self.assertIn("simulated 0 s", r.stderr)

    def test_summary_after_a_failed_output_counts_the_steps_made(self):
        # The simulation runs ahead of the renderers: when the first write
        # fails, steps were made that no output has.  The summary counts
        # those (its sub-steps and energy are theirs) and says how far the
        # outputs got ("simulated 0 s: 0 steps (10 sub-steps ...)" before).
        s = self.scene()
        r = self.rbsim("run", s, "--json", "/dev/full")
        self.assertEqual(r.returncode, 4, r.stderr)
        m = re.search(r"simulated ([^ ]+) s: (\d+) steps \((\d+) sub-steps", r.stdout)
        self.assertIsNotNone(m, r.stdout)
        t, steps, subs = float(m.group(1)), int(m.group(2)), int(m.group(3))
        self.assertAlmostEqual(t, steps * 0.001, places=9)
        self.assertGreaterEqual(subs, steps)
        if steps > 0:
            self.assertIn("frames: up to frame 0 (t = 0 s) reached the outputs; the "
                          "simulation had made %d more when the run stopped" % steps,
                          r.stdout)
        # Ahead for sure: the CSV on a pipe nobody reads blocks the
        # renderer (64 KiB of rows, 20 balls: a dozen frames) while the
        # simulation fills the reel; SIGTERM ends the run, and the blocked
        # write, still unread, is given up (its note says so) -- the pipe
        # is read only once the process has ended.  Tried up to three
        # times, waiting longer each time, in case a loaded machine has
        # not filled the pipe yet.  Balls falling free take one sub-step a
        # step.
        fall = [{"name": "ball%d" % k, "type": "sphere", "radius": 0.1, "mass": 1,
                 "position": [k, 0, 1000]} for k in range(20)]
        s2 = self.scene("fall.json", simulation={"steps": 100000, "dt": 0.001},
                        bodies=fall)
        for wait in (1.0, 2.0, 4.0):
            p = subprocess.Popen([RBSIM, "run", s2, "--csv", "-"], cwd=self.dir,
                                 stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE)
            time.sleep(wait)
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=60)
            finally:
                if p.poll() is None:
                    p.kill()
            _, err = p.communicate(timeout=60)
            err = err.decode()
            if "given up" in err:
                break
        else:
            self.skipTest("the CSV write never blocked before the signal")
        self.assertEqual(p.returncode, 128 + signal.SIGTERM, err)
        m = re.search(r"simulated ([^ ]+) s: (\d+) steps \((\d+) sub-steps", err)
        self.assertIsNotNone(m, err)
        steps, subs = int(m.group(2)), int(m.group(3))
        self.assertEqual(subs, steps, err)
        m2 = re.search(r"frames: up to frame (\d+) \(t = [^ ]+ s\) reached the outputs; "
                       r"the simulation had made (\d+) more", err)
        self.assertIsNotNone(m2, err)
        self.assertEqual(int(m2.group(1)) + int(m2.group(2)), steps, err)

    def test_steps_zero_flag_as_scene(self):
        # --steps 0 is frame 0 only, exactly as "steps": 0 in the scene.
        sim = dict(SCENE["simulation"], steps=0)
        a = self.rbsim("run", self.scene("zero.json", simulation=sim),
                       "--csv", "a.csv", "--quiet")
        self.assertEqual(a.returncode, 0, a.stderr)
        b = self.rbsim("run", self.scene(), "--steps", "0", "--csv", "b.csv",
                       "--quiet")
        self.assertEqual(b.returncode, 0, b.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("b.csv")), 1)
        with open(self.path("a.csv"), "rb") as fa, \
                open(self.path("b.csv"), "rb") as fb:
            self.assertEqual(fa.read(), fb.read())

    def test_every_limit_is_one_everywhere(self):
        # The flag, the scene key and the PNG renderer share 1..2^31-1, and
        # each message gives the range and the value as written.
        top = 2147483647
        r = self.rbsim("run", self.scene(), "--every", str(top), "--csv",
                       "a.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted({int(x[0]) for x in
                                 self.read_csv(self.path("a.csv"))}), [0, 300])
        for value in ("2147483648", "3000000000", "5000000000"):
            s = self.scene("ev.json", renderers=[
                {"type": "csv", "path": "ev.csv", "every": int(value)}])
            r = self.rbsim("check", s)
            self.assertEqual(r.returncode, 3, r.stderr)
            self.assertIn("must be an integer from 1 to 2147483647 (2^31 - 1), "
                          "got " + value, r.stdout + r.stderr)
            r = self.rbsim("run", self.scene(), "--every", value, "--png", "pd")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("from 1 to 2147483647 (2^31 - 1), got '%s'" % value,
                          r.stderr)
            self.assertNotIn("e+09", r.stderr)
        r = self.rbsim("run", self.scene(), "--steps", "3", "--every",
                       str(top), "--png", "pd", "--quiet")
        if "without SDL" not in r.stderr:
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(sorted(os.listdir(self.path("pd"))),
                             ["contact_sheet.png", "frame_000000.png",
                              "frame_000003.png"])

    def test_png_folder_that_cannot_be_made_is_a_usage_error(self):
        # As --csv into a file's name: exit 2 before the run, nothing
        # written, the message names the file in the way; a scene's sdl
        # entry: exit 3 at its place.
        s = self.scene()
        probe = self.rbsim("run", s, "--steps", "1", "--png", "probe",
                           "--quiet")
        if "without SDL" in probe.stderr:
            self.skipTest("built without SDL")
        with open(self.path("afile"), "w") as f:
            f.write("x")
        # A ".." after a folder still to be made steps back out of it
        # (mkdir -p makes it a real folder): "new/../afile" is "afile".
        for folder in ("afile", "afile/sub", "afile/sub/deeper",
                       "new/../afile/png", "new/./../afile/png",
                       "a/b/../../afile/png", "a/b/..//../afile"):
            r = self.rbsim("run", s, "--steps", "3", "--png", folder,
                           "--csv", "kept.csv")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn('"afile" exists and is not a folder', r.stderr)
            self.assertFalse(os.path.exists(self.path("kept.csv")))
            self.assertFalse(os.path.exists(self.path("new")))
            self.assertFalse(os.path.exists(self.path("a")))
        # ... and into a folder that can be made it runs, making the folders
        # on the way as written.
        r = self.rbsim("run", s, "--steps", "2", "--png", "new/../made/png",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.isfile(self.path("made/png/frame_000002.png")))
        with open(self.path("afile")) as f:
            self.assertEqual(f.read(), "x")
        bad = self.scene("badpng.json", renderers=[
            {"type": "sdl", "path": "afile/png", "window": False}])
        r = self.rbsim("run", bad, "--steps", "3")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("renderers[0] (sdl)", r.stderr)
        self.assertIn('"afile" exists and is not a folder', r.stderr)

    def test_no_output_among_the_png_folder_files(self):
        # A file the sdl renderer writes in its folder (frame_NNNNNN.png,
        # contact_sheet.png, viewK/frame_NNNNNN.png) cannot be another
        # output: exit 2, nothing written.  Other names in the folder can.
        s = self.scene()
        probe = self.rbsim("run", s, "--steps", "1", "--png", "probe",
                           "--quiet")
        if "without SDL" in probe.stderr:
            self.skipTest("built without SDL")
        cases = [
            (["--png", "pd", "--csv", "pd/frame_000003.png"], "frame_NNNNNN.png"),
            (["--png", "pd", "--stats", "pd/contact_sheet.png"],
             "contact_sheet.png"),
            (["--png", "pd/", "--json", "./pd//frame_1234567.png"],
             "frame_NNNNNN.png"),
        ]
        for extra, what in cases:
            r = self.rbsim("run", s, "--steps", "5", *extra)
            self.assertEqual(r.returncode, 2, (extra, r.stderr))
            self.assertIn("the sdl output writes in its folder", r.stderr)
            self.assertIn(what, r.stderr)
            self.assertFalse(os.path.exists(self.path("pd")), extra)
        os.mkdir(self.path("pk"))
        r = self.rbsim("run", s, "--steps", "5", "--png", "pk",
                       "--checkpoint", "pk/frame_000000.png")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("the sdl output writes in its folder 'pk' "
                      "(frame_NNNNNN.png)", r.stderr)
        self.assertEqual(os.listdir(self.path("pk")), [])
        # Two views, not tiled: viewK/ for K < 2, and no frames in DIR.
        views = [{"position": [3, -3, 2], "target": [0, 0, 0]},
                 {"position": [-3, 3, 2], "target": [0, 0, 0]}]
        sv = self.scene("views.json", renderers=[
            {"type": "sdl", "path": "pv", "views": views, "window": False}])
        r = self.rbsim("run", sv, "--steps", "5", "--csv",
                       "pv/view1/frame_000005.png")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("viewK/frame_NNNNNN.png", r.stderr)
        # The viewK folders themselves: a file output there was made first
        # and the renderer failed (exit 4); a checkpoint there ran the whole
        # run, then failed to save (exit 4).  Refused before the run, and by
        # check when both are scene entries (exit 3).
        for extra in (["--csv", "pv/view1"], ["--json", "./pv//view0"],
                      ["--checkpoint", "pv/view1"]):
            os.makedirs(self.path("pv"), exist_ok=True)
            r = self.rbsim("run", sv, "--steps", "5", *extra)
            self.assertEqual(r.returncode, 2, (extra, r.stderr))
            self.assertIn("is a folder the sdl output makes in its folder "
                          "'pv' (viewK", r.stderr)
            self.assertEqual(os.listdir(self.path("pv")), [], extra)
        shutil.rmtree(self.path("pv"))
        self.scene("views2.json", renderers=[
            {"type": "sdl", "path": "pv", "views": views, "window": False},
            {"type": "csv", "path": "pv/view1"}])
        for cmd in ("check", "run"):
            r = self.rbsim(cmd, "views2.json")
            self.assertEqual(r.returncode, 3, (cmd, r.stdout + r.stderr))
            self.assertIn("renderers[1].path: the csv output 'pv/view1' is a "
                          "folder the sdl output makes", r.stdout + r.stderr)
        self.assertFalse(os.path.exists(self.path("pv")))
        for name in ("pv/frame_000005.png", "pv/view2/frame_000005.png",
                     "pv/frame_00005.png", "pv/frame_0000005.png",
                     "pv/run.csv"):
            r = self.rbsim("run", sv, "--steps", "5", "--csv", name, "--quiet")
            self.assertEqual(r.returncode, 0, (name, r.stderr))
            self.assertEqual(self.assert_whole_frames(self.path(name)), 6)
        r = self.rbsim("run", s, "--steps", "5", "--png", "pn", "--csv",
                       "pn/frame_000003.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(
            self.path("pn/frame_000003.csv")), 6)

    def test_png_folder_holds_only_this_runs_frames(self):
        # A 10-step run into the folder of an earlier 30-step one left
        # frame_000011..030.png beside its own frames, so a glob of the
        # folder mixed two runs.  The frames (and contact sheet) of the
        # renderer's naming that an earlier run left are removed when the
        # run starts, and a note says so (not with --quiet); other files
        # stay.  A resumed run keeps the frames up to its checkpoint's
        # (the first run's part of the sequence) and removes those above.
        s = self.scene()
        probe = self.rbsim("run", s, "--steps", "1", "--png", "probe", "--quiet")
        if "without SDL" in probe.stderr:
            self.skipTest("built without SDL")
        frames = lambda lo, hi: ["frame_%06d.png" % k for k in range(lo, hi + 1)]
        r = self.rbsim("run", s, "--steps", "30", "--png", "pd", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(self.path("pd"))),
                         ["contact_sheet.png"] + frames(0, 30))
        with open(self.path("pd/notes.txt"), "w") as f:
            f.write("mine\n")
        os.mkdir(self.path("pd/frame_000099.png"))  # not a file: left alone
        r = self.rbsim("run", s, "--steps", "10", "--png", "pd")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("rbsim: note: removed 32 files an earlier run left in the "
                      "png folder 'pd' (frames 0 to 30, contact_sheet.png), so "
                      "that it holds this run's files only\n", r.stderr)
        self.assertEqual(sorted(os.listdir(self.path("pd"))),
                         ["contact_sheet.png"] + frames(0, 10) +
                         ["frame_000099.png", "notes.txt"])
        os.rmdir(self.path("pd/frame_000099.png"))
        # --quiet: no note, the same removal
        r = self.rbsim("run", s, "--steps", "3", "--every", "2", "--png", "pd",
                       "--quiet")
        self.assertEqual((r.returncode, r.stderr), (0, ""))
        self.assertEqual(sorted(os.listdir(self.path("pd"))),
                         ["contact_sheet.png", "frame_000000.png",
                          "frame_000002.png", "frame_000003.png", "notes.txt"])
        # A resumed run: frames 0..10 are the first run's, kept as they are;
        # a stale frame above is removed.
        r = self.rbsim("run", s, "--steps", "10", "--png", "pr", "--checkpoint",
                       "c.ckpt", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        kept = os.stat(self.path("pr/frame_000010.png")).st_ino
        shutil.copy(self.path("pr/frame_000010.png"), self.path("pr/frame_000050.png"))
        r = self.rbsim("run", s, "--steps", "20", "--resume", "c.ckpt",
                       "--png", "pr")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("rbsim: note: removed 1 file an earlier run left in the "
                      "png folder 'pr' (frame 50), so that it holds this run's files "
                      "only\n",
                      r.stderr)
        self.assertEqual(sorted(os.listdir(self.path("pr"))),
                         ["contact_sheet.png"] + frames(0, 20))
        self.assertEqual(os.stat(self.path("pr/frame_000010.png")).st_ino, kept)
        # Two views, not tiled: the frames in view0/ and view1/ alike.
        views = [{"position": [3, -3, 2], "target": [0, 0, 0]},
                 {"position": [-3, 3, 2], "target": [0, 0, 0]}]
        sv = self.scene("views.json", renderers=[
            {"type": "sdl", "path": "pv", "views": views, "window": False,
             "contact_sheet": False}])
        for steps in ("8", "4"):
            r = self.rbsim("run", sv, "--steps", steps, "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(self.path("pv"))), ["view0", "view1"])
        for v in ("view0", "view1"):
            self.assertEqual(sorted(os.listdir(self.path("pv/" + v))), frames(0, 4))

    def test_stdin_end_does_not_stop_the_run(self):
        s = self.scene()
        r = self.rbsim("run", s, "--csv", "a.csv", "--steps", "400")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("a.csv")), 401)
        # stdin closed outright (not even /dev/null)
        r = subprocess.run([RBSIM, "run", s, "--csv", "b.csv", "--steps",
                            "400"], cwd=self.dir, capture_output=True,
                           text=True, timeout=120,
                           preexec_fn=lambda: os.close(0))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("b.csv")), 401)

    def test_a_reel_too_large_says_its_size_and_the_way_out(self):
        # --reel 1048576 (the largest allowed) for 50 bodies under a 1 GB
        # address space: "out of memory or buffer too small" named neither
        # the size nor what to change (a probe of session 46).
        with open(shutil.which(RBSIM) or RBSIM, "rb") as f:
            if b"__asan_init" in f.read():
                self.skipTest("AddressSanitizer reserves its shadow memory beyond "
                              "any RLIMIT_AS")
        bodies = [dict(SCENE["bodies"][1], name="b%d" % i,
                       position=[3.0 * i, 0, 1]) for i in range(49)]
        s = self.scene("many.json", bodies=[SCENE["bodies"][0]] + bodies)

        def limit():
            resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))
        r = self.rbsim("run", s, "--steps", "2", "--reel", "1048576", "--quiet",
                       "--csv", "a.csv", preexec_fn=limit)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertRegex(r.stderr, r"cannot make a reel of 1048576 frames of 50 bodies "
                                   r"\([0-9.e+]+ MB\): out of memory; a reel of fewer "
                                   r"frames \(reel_capacity\) needs less")
        self.assertFalse(os.path.exists(self.path("a.csv")))

    def test_no_input_never_leaves_the_run_paused(self):
        # --paused, or pauses on collisions, with nothing on stdin: the run
        # must still complete by itself.
        s = self.scene()
        r = self.rbsim("run", s, "--paused", "--csv", "a.csv", timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("end of input: resumed", r.stdout)
        self.assertEqual(self.assert_whole_frames(self.path("a.csv")), 301)
        # standard input that cannot be read (a folder: EISDIR) was taken
        # for an end of input without a word (a probe of session 46)
        folder = os.open(self.dir, os.O_RDONLY)
        try:
            r = self.rbsim("run", s, "--paused", "--csv", "c.csv", stdin=folder,
                           timeout=60)
        finally:
            os.close(folder)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("rbsim: note: standard input: cannot read commands: Is a "
                      "directory; the run goes on without them\nno input: resumed "
                      "(no command could resume the run later)\n", r.stdout)
        self.assertEqual(self.assert_whole_frames(self.path("c.csv")), 301)
        sim = dict(SCENE["simulation"], pause_on_collision=True)
        s = self.scene("poc.json", simulation=sim)
        r = self.rbsim("run", s, "--csv", "b.csv", timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("pause_on_collision is ignored", r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("b.csv")), 301)

    def test_commands_from_stdin(self):
        s = self.scene()
        p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--steps",
                              "100000", "--csv", "q.csv"], cwd=self.dir,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        try:
            out, err = p.communicate(
                "help\nbogus 1 2\nstep 0\nspeed fast\npause\nstatus\n"
                "step 3\nresume\n\nquit\n", timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        self.assertEqual(p.returncode, 0, err)
        self.assertIn("commands:", out)
        self.assertIn("unknown command 'bogus'; commands:", out)
        self.assertIn("step: expected a whole number", out)
        self.assertIn("speed: expected a factor", out)
        self.assertIn("paused at frame", out)
        self.assertIn("stepping 3 frames", out)
        self.assertIn("stopped at frame", out)
        n = self.assert_whole_frames(self.path("q.csv"))
        self.assertLess(n, 100001)  # quit, not the end

    def test_odd_command_lines(self):
        # A 10 kB line is refused once (not once per 1 kB read); a line with
        # a NUL or an escape sequence is refused naming the byte (a NUL cut
        # it short -- "status\\0junk" ran status -- and the unknown-command
        # reply echoed escapes raw, driving the terminal); CR LF ends a
        # line as LF does.  (The probe of session 38; C1 controls, overrides
        # and invalid UTF-8 since session 49.)
        s = self.scene()
        p = subprocess.Popen([RBSIM, "run", s, "--paused", "--steps", "1000",
                              "--csv", "o.csv"], cwd=self.dir,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE)
        try:
            out, err = p.communicate(
                b"x" * 10000 + b"\nstatus\x00junk\n\x1b]0;title\x07\n"
                b"fo\xc2\x9bo\nhelp x\xe2\x80\xaey\nspeed \xff\n"
                b"status\r\nquit\n", timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        out = out.decode("utf-8", "replace")
        self.assertEqual(p.returncode, 0, err)
        self.assertEqual(out.count("line too long"), 1, out)
        self.assertIn("control characters (byte 0x00 at 7): ignored", out)
        self.assertIn("control characters (byte 0x1b at 1): ignored", out)
        # a C1 control (U+009B, a one-character ESC [) and a bidirectional
        # override were echoed raw by "unknown command", invalid UTF-8 too
        self.assertIn("characters (U+009B at byte 3): ignored", out)
        self.assertIn("characters (U+202E at byte 7): ignored", out)
        self.assertIn("a command must be UTF-8 (byte 0xff at 7): ignored", out)
        self.assertNotIn("\x1b", out)
        self.assertNotIn("\u009b", out)
        self.assertNotIn("\u202e", out)
        self.assertEqual(out.count("frame 0 of 1000"), 1, out)  # the one status
        self.assertIn("stopped at frame", out)

    def test_last_line_without_newline_is_a_command(self):
        # At end of input a last line without its newline is a line, as a
        # shell takes it: printf 'quit' | rbsim run ... stopped nothing
        # (the partial line was thrown away: the run went to its end) and
        # printf 'status' got no reply.  Paused runs, so only the commands
        # move them: "quit" stops at frame 0; "status" answers, then end of
        # input resumes the run, which ends by itself.
        s = self.scene()
        for name, data in (("q", b"status\nquit"), ("s", b"status")):
            p = subprocess.Popen([RBSIM, "run", s, "--paused", "--steps", "1000",
                                  "--csv", name + ".csv"], cwd=self.dir,
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
            try:
                out, err = p.communicate(data.decode(), timeout=60)
            finally:
                if p.poll() is None:
                    p.kill()
            self.assertEqual(p.returncode, 0, err)
            self.assertEqual(out.count("frame 0 of 1000"), 1, out)
            frames = self.assert_whole_frames(self.path(name + ".csv"))
            if name == "q":
                self.assertIn("stopped at frame 0", out)
                self.assertNotIn("end of input", out)
                self.assertEqual(frames, 1)  # frame 0 only: quit while paused there
            else:
                self.assertIn("end of input: resumed", out)
                self.assertEqual(frames, 1001)

    def test_paused_start_and_step(self):
        s = self.scene()
        p = subprocess.Popen([RBSIM, "run", s, "--paused", "--steps",
                              "1000", "--csv", "p.csv"], cwd=self.dir,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        seen = []
        try:
            p.stdin.write("step 10\n")
            p.stdin.flush()
            seen.append(p.stdout.readline())  # "stepping 10 frames ..."
            deadline = time.time() + 60
            while time.time() < deadline:
                p.stdin.write("status\n")
                p.stdin.flush()
                seen.append(p.stdout.readline())
                if "frame 10 of 1000" in seen[-1]:
                    break
                time.sleep(0.05)
            time.sleep(0.2)  # paused: nothing more may come
            p.stdin.write("status\nquit\n")
            p.stdin.flush()
            out, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        self.assertEqual(p.returncode, 0, err)
        self.assertIn("stepping 10 frames", seen[0])
        self.assertIn("frame 10 of 1000", seen[-1])
        self.assertIn("frame 10 of 1000", out)
        self.assertIn("paused", out)
        self.assertEqual(self.assert_whole_frames(self.path("p.csv")), 11)

    def test_readme_examples_run(self):
        # Every "$R ..." line of the README's "Using it" block, run as
        # written in a copy of scenes/ (one of them once named a scene the
        # method it asked for refuses, and exited 4).
        top = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
        with open(os.path.join(top, "README.md")) as f:
            text = f.read()
        block = text.split("## Using it", 1)[1].split("```sh", 1)[1].split("```", 1)[0]
        lines = [l.split("#", 1)[0].split()[1:] for l in block.splitlines()
                 if l.startswith("$R ")]
        self.assertGreaterEqual(len(lines), 8)
        shutil.copytree(os.path.join(top, "scenes"), self.path("scenes"))
        for args in lines:
            r = self.rbsim(*args, timeout=300)
            self.assertEqual(r.returncode, 0, (args, r.stderr))
        # The checkpoint example keeps what it says: the first run's CSV
        # plus the resumed one's rows are the uninterrupted run's bytes (it
        # once read the first part from the scene's own out/pile.csv, which
        # the resumed run replaced with frames 1001.. only).
        first = [a for a in lines if "--checkpoint" in a]
        rest = [a for a in lines if "--resume" in a]
        self.assertEqual((len(first), len(rest)), (1, 1))
        first, rest = first[0], rest[0]
        self.assertEqual(first[:2], rest[:2])
        r = self.rbsim("run", first[1], "--csv", "whole.csv", "--quiet",
                       timeout=300)
        self.assertEqual(r.returncode, 0, r.stderr)
        parts = []
        for args in (first, rest):
            self.assertIn("--csv", args, args)
            with open(self.path(args[args.index("--csv") + 1]), "rb") as f:
                parts.append(f.read())
        with open(self.path("whole.csv"), "rb") as f:
            whole = f.read()
        self.assertEqual(parts[0] + parts[1].split(b"\n", 1)[1], whole)

    def test_check_and_explain_refuse_what_event_refuses(self):
        # (they passed it; run then failed at step 1 with exit 4)
        sim = {"steps": 10, "method": "event", "mutual_gravity": True}
        s = self.scene(simulation=sim)
        want = ("scene.json:%d:%d: simulation.mutual_gravity: method \"event\" "
                "does not support mutual gravity")
        with open(s) as f:
            text = f.read()
        head = text[:text.index('"mutual_gravity": true') + len('"mutual_gravity": ')]
        where = (head.count("\n") + 1, len(head) - head.rfind("\n"))
        for cmd in ("check", "explain"):
            r = self.rbsim(cmd, "scene.json")
            self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
            self.assertIn(want % where, r.stdout)
        r = self.rbsim("run", "scene.json", "--csv", "ev.csv")
        self.assertEqual(r.returncode, 3, r.stderr)
        # --method event on a scene of another method: the same, from the
        # command line, a usage error alike (explain said it on stdout with
        # exit 3, as a scene error: a probe of session 46)
        sim = {"steps": 10, "mutual_gravity": True}
        self.scene(simulation=sim)
        for cmd in (["explain", "scene.json"], ["run", "scene.json"]):
            r = self.rbsim(*cmd, "--method", "event")
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertEqual(r.stdout, "")
            self.assertIn("command line: --method: method \"event\" does not "
                          "support mutual gravity", r.stderr)

    def test_convert_round_trip(self):
        s = self.scene()
        os.mkdir(self.path("txt"))
        r = self.rbsim("convert", s, self.path("txt/config.txt"))
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("check", self.path("txt/config.txt"))
        self.assertEqual(r.returncode, 0, r.stdout)
        # its objects file given for the scene says what it seems to be (it
        # said only "expected key = value": a probe of session 46)
        r = self.rbsim("check", self.path("txt/objects.txt"))
        self.assertEqual(r.returncode, 3)
        self.assertIn("(a body line: this looks like an objects file; give the "
                      "config.txt that names it)", r.stdout)
        r = self.rbsim("convert", self.path("txt/config.txt"),
                       self.path("back.json"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rbsim("convert", s, "x.yaml").returncode, 2)
        # ".JSON" as the loader reads it; a folder named as such (both said
        # "cannot tell the format": a probe of session 46)
        self.assertEqual(self.rbsim("convert", s, "up.JSON").returncode, 0)
        # ".TXT" alike (it said "cannot tell the format": a probe of
        # session 51), and the scene it writes loads back
        r = self.rbsim("convert", s, "up.TXT")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rbsim("check", "up.TXT").returncode, 0)
        r = self.rbsim("convert", s, "txt")
        self.assertEqual(r.returncode, 2)
        self.assertEqual(r.stderr, "rbsim convert: OUT 'txt' is a folder: name "
                         "'txt/config.txt' for the config.txt format, or a "
                         "*.json file\n")
        self.assertEqual(self.rbsim("convert", s).returncode, 2)
        self.assertEqual(self.rbsim("convert", self.path("nope.json"),
                                    "o.json").returncode, 3)
        # The converted scenes run to the same bytes.
        outs = []
        for i, sc in enumerate((s, self.path("txt/config.txt"),
                                self.path("back.json"))):
            r = self.rbsim("run", sc, "--csv", "c%d.csv" % i, "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(self.path("c%d.csv" % i), "rb") as f:
                outs.append(f.read())
        self.assertEqual(outs[0], outs[1])
        self.assertEqual(outs[0], outs[2])

    def test_missing_folders_are_named(self):
        # convert into two missing folders said only "No such file or
        # directory"; it names the folder now (one missing folder is made,
        # as for --csv, whose missing folder the run makes); --checkpoint
        # says its folder is not made.
        s = self.scene()
        r = self.rbsim("convert", s, "nz/a/b.json")
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("cannot write 'nz/a/b.json': folder 'nz/a' does not "
                      "exist (a save makes one missing folder, not more)",
                      r.stderr)
        r = self.rbsim("convert", s, "scene.json/b.json")
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("'scene.json' is not a folder", r.stderr)
        self.assertFalse(os.path.exists(self.path("nz")))
        r = self.rbsim("convert", s, "nz/b.json")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "2", "--csv", "nx/a.csv",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.isfile(self.path("nx/a.csv")))
        r = self.rbsim("run", s, "--steps", "2", "--checkpoint", "ny/ck.bin")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("folder 'ny' does not exist (a checkpoint's folder is "
                      "not made: make it first)", r.stderr)

    def test_convert_never_writes_over_its_input(self):
        # Onto the scene itself, or onto a file a text scene reads (its
        # materials.txt), convert refuses and leaves the input whole (it
        # wrote over it, comments gone, or wrote a config into the material
        # table); a read-only file is not replaced either.  (A probe of
        # session 38.)
        s = self.scene()
        with open(s) as f:
            before = f.read()
        # The library's save refuses it (RBS_E_OWN_INPUT) before anything
        # is written, and convert makes that a usage error (exit 2) naming
        # OUT and the file of IN it is, through any spelling of the path, a
        # symbolic link, or standard input redirected from OUT (it ran the
        # save and exited 4 "cannot write": a probe of session 47; then
        # convert checked the paths itself, apart from the library).
        link = self.path("link.json")
        os.symlink(s, link)
        spellings = [s, os.path.join(self.dir, ".", os.path.basename(s)),
                     os.path.join(self.dir, "..", os.path.basename(self.dir),
                                  os.path.basename(s)), link]
        for out in spellings:
            r = self.rbsim("convert", s, out)
            self.assertEqual(r.returncode, 2, (out, r.stderr))
            self.assertEqual(
                r.stderr,
                "rbsim convert: OUT '%s' would write over its input: cannot "
                "write '%s': %s a file this scene was read from; write "
                "elsewhere\n" % (out, out, "it is" if out == s else "it is '%s'," % s))
        with open(s) as stdin:
            r = subprocess.run([RBSIM, "convert", "-", s], stdin=stdin,
                               capture_output=True, text=True, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("OUT '%s' would write over its input: cannot write '%s': it "
                      "is '/dev/stdin', a file this scene was read from; write "
                      "elsewhere (IN '-' is standard input)" % (s, s), r.stderr)
        with open(s) as f:
            self.assertEqual(f.read(), before)
        # an invalid IN onto itself: its scene errors (exit 3), nothing written
        bad = self.path("bad.json")
        with open(bad, "w") as f:
            f.write("{\n")
        r = self.rbsim("convert", bad, bad)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("bad.json:2:1: ", r.stderr)
        with open(bad) as f:
            self.assertEqual(f.read(), "{\n")
        txt = self.path("t/config.txt")
        self.assertEqual(self.rbsim("convert", s, txt).returncode, 0)
        with open(self.path("t/materials.txt")) as f:
            table = f.read()
        r = self.rbsim("convert", txt, self.path("t/materials.txt"))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("OUT '%s' would write over its input: cannot write '%s': "
                      "it is a file this scene was read from"
                      % ((self.path("t/materials.txt"),) * 2), r.stderr)
        with open(self.path("t/materials.txt")) as f:
            self.assertEqual(f.read(), table)
        # a text OUT whose tables beside it are the scene's
        other = self.path("t/other.txt")
        shutil.copy(txt, other)
        r = self.rbsim("convert", other, txt)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("OUT '%s' would write over its input: cannot write '%s'"
                      % (txt, self.path("t/materials.txt")), r.stderr)
        with open(self.path("t/materials.txt")) as f:
            self.assertEqual(f.read(), table)
        ro = self.path("ro.json")
        with open(ro, "w") as f:
            f.write("OLD\n")
        os.chmod(ro, 0o444)
        r = self.rbsim("convert", s, ro)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("read-only", r.stderr)
        with open(ro) as f:
            self.assertEqual(f.read(), "OLD\n")
        self.assertEqual(sorted(n for n in os.listdir(self.dir) if ".tmp" in n), [])

    def test_convert_writes_everything_or_nothing(self):
        # objects.txt cannot be written (a folder is in its place): the old
        # config.txt stays, no materials.txt or temporary appears, and the
        # message names objects.txt and why (exit 4).
        s = self.scene()
        d = self.path("half")
        os.mkdir(d)
        with open(os.path.join(d, "config.txt"), "w") as f:
            f.write("old\n")
        os.mkdir(os.path.join(d, "objects.txt"))
        r = self.rbsim("convert", s, os.path.join(d, "config.txt"))
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("objects.txt': is a folder", r.stderr)
        self.assertEqual(sorted(os.listdir(d)), ["config.txt", "objects.txt"])
        with open(os.path.join(d, "config.txt")) as f:
            self.assertEqual(f.read(), "old\n")
        # objects.txt too large to write, into a folder convert makes: the
        # message names objects.txt (not config.txt, flushed last of all on
        # a full disk) and the folder it made is gone again.
        bodies = SCENE["bodies"] + [
            {"name": "s%d" % k, "type": "sphere", "radius": 0.01, "mass": 1,
             "position": [0.03 * k, 2, 0.5]} for k in range(60)]
        big = self.scene("big.json", bodies=bodies)
        r = self.rbsim("convert", big, "pile/config.txt",
                       preexec_fn=file_size_limit(4096, signal.SIG_IGN))
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("cannot write 'pile/objects.txt': File too large", r.stderr)
        self.assertFalse(os.path.exists(self.path("pile")))
        if os.geteuid() == 0:  # a full disk: a small tmpfs (needs root)
            mnt = self.path("small")
            os.mkdir(mnt)
            m = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=8k",
                                "tmpfs", mnt], capture_output=True, text=True)
            if m.returncode == 0:
                try:
                    r = self.rbsim("convert", big, "small/pile/config.txt")
                    self.assertEqual(r.returncode, 4, r.stderr)
                    self.assertIn("cannot write 'small/pile/objects.txt': No "
                                  "space left on device", r.stderr)
                    self.assertEqual(os.listdir(mnt), [])
                finally:
                    subprocess.run(["umount", mnt], check=True)
        # a reason that names the folder, not "input/output error" (nor
        # only the OS's "No such file or directory")
        r = self.rbsim("convert", s, self.path("no/such/dir/x.json"))
        self.assertEqual(r.returncode, 4)
        self.assertIn("/no/such/dir' does not exist (a save makes one missing "
                      "folder, not more)", r.stderr)

    def test_scene_through_a_pipe(self):
        # A scene read through a pipe, /dev/stdin or a FIFO named without
        # .json is read once: telling its format used to eat its start.
        s = self.scene()
        with open(s) as f:
            text = f.read()
        r = self.rbsim("run", s, "--csv", "file.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.path("file.csv"), "rb") as f:
            want = f.read()
        r = self.rbsim("check", "/dev/stdin", stdin=None, input=text)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("/dev/stdin: ok", r.stdout)
        r = self.rbsim("run", "/dev/stdin", "--csv", "pipe.csv", "--quiet",
                       stdin=None, input=text)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        with open(self.path("pipe.csv"), "rb") as f:
            self.assertEqual(f.read(), want)
        r = self.rbsim("convert", "/dev/stdin", self.path("back.json"),
                       stdin=None, input=text)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.rbsim("check", "back.json").returncode, 0)
        # a FIFO named "scene": the writer's data, not a second open that
        # waits for a writer for ever
        fifo = self.path("scene")
        os.mkfifo(fifo)
        p = subprocess.Popen([RBSIM, "run", fifo, "--csv", "fifo.csv",
                              "--quiet"], cwd=self.dir, text=True,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            with open(fifo, "w") as f:
                f.write(text)
            out, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
                p.wait()
        self.assertEqual(p.returncode, 0, out + err)
        with open(self.path("fifo.csv"), "rb") as f:
            self.assertEqual(f.read(), want)
        # a config.txt through a pipe: its files are looked for in the
        # current folder (they were looked for in /dev: a probe of session
        # 46), and the error says so
        os.mkdir(self.path("txt"))
        r = self.rbsim("convert", s, self.path("txt/config.txt"))
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.path("txt/config.txt")) as f:
            config = f.read()
        r = self.rbsim("check", "/dev/stdin", stdin=None, input=config)
        self.assertEqual(r.returncode, 3)
        self.assertIn("'/dev/stdin' is a descriptor: the file names in it "
                      "are looked for in the current folder", r.stdout)
        r = subprocess.run([RBSIM, "check", "/dev/stdin"], input=config,
                           capture_output=True, text=True, timeout=120,
                           cwd=self.path("txt"))
        self.assertEqual(r.returncode, 0, r.stdout)
        # a stream without end is refused at the size limit
        with open("/dev/zero", "rb") as zero:
            r = self.rbsim("check", "/dev/stdin", stdin=zero, timeout=60)
        self.assertEqual(r.returncode, 3)
        self.assertIn("/dev/stdin: cannot read '/dev/stdin': larger than "
                      "268435456 bytes", r.stdout)

    def test_demo(self):
        r = self.rbsim("run", timeout=300)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("built-in demonstration", r.stdout)
        checks = [l for l in r.stdout.splitlines() if l.startswith("check:")]
        self.assertEqual(len(checks), 2, r.stdout)
        for l in checks:
            self.assertTrue(l.endswith("ok"), l)
        self.assertIn("sqrt(2h/g)", r.stdout)
        self.assertIn("5/7 v0", r.stdout)
        # rolling is compared in the speed and in spin x radius, each
        # printed to 6 digits equal to 5/7 of 2 m/s (session 45: the spin
        # was printed, not compared)
        self.assertIn("rolling speed of \"slider\" 1.428571 m/s, spin x radius 1.428571 m/s",
                      r.stdout)
        for key in ("steps/s", "sub-steps", "rollbacks", "collisions",
                    "wall time", "drift"):
            self.assertIn(key, r.stdout)
        rows = self.read_csv(self.path("rbsim-demo/demo.csv"))
        self.assertEqual(int(rows[-1][0]), 2000)
        with open(self.path("rbsim-demo/stats.csv")) as f:
            self.assertEqual(f.readline().strip(), STATS_HEADER)

    def test_demo_refuses_what_breaks_it(self):
        # A file where the demonstration's folder goes was exit 4 "cannot
        # create folder 'rbsim-demo': File exists"; --steps 5 ran, printed
        # "check: first impact ... FAIL" and exited 4.  Both are usage
        # errors now (exit 2, before the run, nothing written), saying why.
        with open(self.path("rbsim-demo"), "w") as f:
            f.write("mine\n")
        r = self.rbsim("run")
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertIn("the demonstration writes its outputs in the folder "
                      "'rbsim-demo', and 'rbsim-demo' here is not a folder",
                      r.stderr)
        with open(self.path("rbsim-demo")) as f:
            self.assertEqual(f.read(), "mine\n")
        os.remove(self.path("rbsim-demo"))
        for args in (["--steps", "5"], ["--steps=0"], ["--dt", "0.01"],
                     ["--method", "rk4"], ["--slop", "0.01", "--quiet"]):
            r = self.rbsim("run", *args)
            self.assertEqual(r.returncode, 2, (args, r.stdout + r.stderr))
            self.assertIn("rbsim run: %s changes the built-in demonstration"
                          % args[0].split("=")[0], r.stderr)
            self.assertEqual(r.stdout, "")
        self.assertEqual(os.listdir(self.dir), [])

    def test_dash_is_standard_input(self):
        # "-" for the scene is standard input, as for most tools ("rbsim run
        # -" said "cannot open '-'": a probe of session 46), taken as
        # /dev/stdin: the format is told from the bytes (JSON or text), and
        # no commands are read from it.
        s = self.scene()
        want = self.rbsim("run", s, "--csv", "-", "--quiet")
        self.assertEqual(want.returncode, 0, want.stderr)
        with open(s) as f:
            text = f.read()
        r = self.rbsim("run", "-", "--csv", "-", stdin=None, input=text)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, want.stdout)
        self.assertIn("standard input is the scene: no commands", r.stderr)
        # a text scene through the pipe too
        self.assertEqual(self.rbsim("convert", s, "scene.txt").returncode, 0)
        with open(self.path("scene.txt")) as f:
            r = self.rbsim("run", "-", "--csv", "-", "--quiet", stdin=f)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, want.stdout)
        for cmd in ("check", "explain"):
            r = self.rbsim(cmd, "-", stdin=None, input=text)
            self.assertEqual(r.returncode, 0, (cmd, r.stdout, r.stderr))
            self.assertIn("/dev/stdin", r.stdout)
        r = self.rbsim("check", "-", stdin=None, input="{\"bodies\": 3}")
        self.assertEqual(r.returncode, 3)
        self.assertIn("/dev/stdin:1:", r.stdout)
        r = self.rbsim("convert", "-", "back.json", stdin=None, input=text)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", "back.json", "--csv", "-", "--quiet")
        self.assertEqual(r.stdout, want.stdout)
        # nothing on standard input (or a blank file not named *.json): said
        # so, where it said 'missing "objects = FILE"'
        for kw in ({}, {"stdin": None, "input": " \n"}):
            r = self.rbsim("run", "-", **kw)
            self.assertEqual(r.returncode, 3, r.stderr)
            self.assertEqual(r.stderr, "/dev/stdin:1:1: empty input: expected a "
                             "scene (a JSON object, or the lines of a "
                             "config.txt)\n")
        with open(self.path("blank.txt"), "w") as f:
            f.write(" \n\n")
        r = self.rbsim("check", "blank.txt")
        self.assertEqual(r.returncode, 3)
        self.assertIn("blank.txt:1:1: empty input: expected a scene", r.stdout)
        # a config.txt redirected from a file: its files come from the
        # current folder, and the error says so
        os.mkdir(self.path("elsewhere"))
        with open(self.path("scene.txt")) as f:
            r = subprocess.run([RBSIM, "check", "-"], stdin=f,
                               capture_output=True, text=True, timeout=120,
                               cwd=self.path("elsewhere"))
        self.assertEqual(r.returncode, 3)
        self.assertIn("'/dev/stdin' is a descriptor: the file names in it are "
                      "looked for in the current folder", r.stdout)
        # --resume - reads the checkpoint from standard input; not both
        r = self.rbsim("run", s, "--steps", "3", "--checkpoint", "ck.bin",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(self.path("ck.bin"), "rb") as f:
            r = subprocess.run([RBSIM, "run", s, "--resume", "-", "--csv", "-",
                                "--quiet"], stdin=f, capture_output=True,
                               cwd=self.dir, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(want.stdout.endswith(
            r.stdout.decode().split("\n", 1)[1]))
        r = self.rbsim("run", "-", "--resume", "-", stdin=None, input=text)
        self.assertEqual(r.returncode, 2)
        self.assertIn("the scene and --resume cannot both be standard input",
                      r.stderr)
        # OUT '-' is refused, naming why (it said "cannot tell the format")
        r = self.rbsim("convert", s, "-")
        self.assertEqual(r.returncode, 2)
        self.assertIn("OUT '-': the converted scene cannot go to standard "
                      "output", r.stderr)


class FaultTests(Base):
    def test_dev_full(self):
        if not os.path.exists("/dev/full"):
            self.skipTest("no /dev/full")
        s = self.scene()
        r = self.rbsim("run", s, "--csv", "/dev/full")
        self.assertEqual(r.returncode, 4)
        self.assertIn("'/dev/full'", r.stderr)
        self.assertIn("No space left on device", r.stderr)
        # the CSV's first write is its header line, before any frame: named
        self.assertIn("header line", r.stderr)
        r = self.rbsim("run", s, "--csv", "ok.csv", "--json", "/dev/full",
                       "--steps", "1000")
        self.assertEqual(r.returncode, 4)
        self.assertIn("json renderer '/dev/full'", r.stderr)
        self.assertIn("frame 0", r.stderr)
        self.assertIn("No space left on device", r.stderr)
        self.assert_whole_frames(self.path("ok.csv"))

    def test_lost_standard_output(self):
        # What a command prints on its standard output (a check's verdict,
        # the help, the version, a run's summary) that cannot be written --
        # a full disk, a closed descriptor -- is an error (exit 4, with a
        # message), not a success (the probe of session 38 found exit 0).
        # Every command says so alike, with the reason (run's summary lost
        # it: the reason is known only at the first flush that fails;
        # explain said "cannot write the output").
        if not os.path.exists("/dev/full"):
            self.skipTest("no /dev/full")
        s = self.scene()
        for args in (["check", s], ["--version"], ["help"], ["help", "run"],
                     ["run", s, "--csv", "ok.csv"], ["explain", s],
                     ["run", s, "--csv", "ok.csv", "--checkpoint", "c.ck"]):
            with open("/dev/full", "w") as full:
                r = subprocess.run([RBSIM] + args, stdin=subprocess.DEVNULL,
                                   stdout=full, stderr=subprocess.PIPE,
                                   text=True, cwd=self.dir, timeout=120)
            self.assertEqual(r.returncode, 4, args)
            self.assertEqual(r.stderr, "rbsim: what it printed on the standard "
                             "output was lost: No space left on device\n", args)
        # the run's own outputs are complete all the same
        self.assert_whole_frames(self.path("ok.csv"))
        # a closed standard output (as `>&-` leaves it)
        r = subprocess.run([RBSIM, "check", s], stdin=subprocess.DEVNULL,
                           stderr=subprocess.PIPE, text=True, cwd=self.dir,
                           timeout=120,
                           preexec_fn=lambda: os.close(1))
        self.assertEqual(r.returncode, 4)
        # it says the descriptor is closed (it said "Broken pipe", from the
        # pipe with no reader put there: a probe of session 46)
        self.assertEqual(r.stderr, "rbsim: what it printed on the standard "
                         "output was lost: Bad file descriptor\n")
        for dump in ("--csv", "--json", "--stats"):
            r = subprocess.run([RBSIM, "run", s, dump, "-"],
                               stdin=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               text=True, cwd=self.dir, timeout=120,
                               preexec_fn=lambda: os.close(1))
            self.assertEqual(r.returncode, 4, dump)
            self.assertIn("write to '-' failed: Bad file descriptor", r.stderr, dump)
            self.assertNotIn("Broken pipe", r.stderr, dump)
        # ... and /dev/null at the closed descriptor is not taken for "-"
        r = subprocess.run([RBSIM, "run", s, "--csv", "/dev/null", "--quiet"],
                           stdin=subprocess.DEVNULL, stderr=subprocess.PIPE,
                           text=True, cwd=self.dir, timeout=120,
                           preexec_fn=lambda: os.close(1))
        self.assertEqual((r.returncode, r.stderr), (0, ""))
        # a failing command keeps its own code, and is told: check's errors
        # go to the standard output, so nothing at all was said
        with open("/dev/full", "w") as full:
            r = subprocess.run([RBSIM, "check", self.path("nope.json")],
                               stdout=full, stderr=subprocess.PIPE,
                               text=True, cwd=self.dir, timeout=120)
        self.assertEqual(r.returncode, 3)
        self.assertIn("standard output was lost: No space left", r.stderr)

    def test_file_too_large_mid_run(self):
        # A file size limit makes the CSV fail part way through a frame: the
        # file must end on the last whole frame, the run stop with exit 4.
        limit = 60000
        limit_size = file_size_limit(limit, signal.SIG_IGN)
        s = self.scene()
        r = subprocess.run([RBSIM, "run", s, "--csv", "big.csv", "--steps",
                            "5000"], cwd=self.dir, capture_output=True,
                           text=True, timeout=120, preexec_fn=limit_size,
                           stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("big.csv", r.stderr)
        self.assertIn("File too large", r.stderr)
        size = os.path.getsize(self.path("big.csv"))
        self.assertLessEqual(size, limit)
        self.assertGreater(size, limit - 1000)  # it failed near the limit
        self.assertGreater(self.assert_whole_frames(self.path("big.csv")), 10)

    def test_rejected_run_keeps_existing_outputs(self):
        """An output that cannot be made (a name too long for the file
        system, /proc) is refused before any output is touched: existing
        files keep their bytes and no new file is left behind."""
        s = self.scene(renderers=[{"type": "csv", "path": "scene_out.csv"}])
        for name, text in (("keep.json", "PRECIOUS\n"),
                           ("scene_out.csv", "MARKER\n")):
            with open(self.path(name), "w") as f:
                f.write(text)
        before = sorted(os.listdir(self.dir))
        for bad in ("s" * 300 + ".csv", "/proc/rbsim-no-such.csv",
                    "/proc/self/status"):
            r = self.rbsim("run", s, "--json", "keep.json", "--csv", "new.csv",
                           "--stats", bad)
            self.assertEqual(r.returncode, 2, (bad, r.stderr))
            self.assertIn("rbsim run: --stats: ", r.stderr)
            self.assertEqual(sorted(os.listdir(self.dir)), before, bad)
            with open(self.path("keep.json")) as f:
                self.assertEqual(f.read(), "PRECIOUS\n")
            with open(self.path("scene_out.csv")) as f:
                self.assertEqual(f.read(), "MARKER\n")

    def test_run_replaces_existing_outputs(self):
        """A run that starts replaces an existing output whole (same
        permissions, written through a symlink) and leaves no temporary."""
        s = self.scene()
        with open(self.path("old.csv"), "w") as f:
            f.write("OLD\n")
        os.chmod(self.path("old.csv"), 0o640)
        os.mkdir(self.path("real"))
        with open(self.path("real/t.jsonl"), "w") as f:
            f.write("OLD\n")
        os.symlink("real/t.jsonl", self.path("link.jsonl"))
        r = self.rbsim("run", s, "--steps", "20", "--csv", "old.csv",
                       "--json", "link.jsonl", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("old.csv")), 21)
        self.assertEqual(os.stat(self.path("old.csv")).st_mode & 0o777, 0o640)
        self.assertTrue(os.path.islink(self.path("link.jsonl")))
        with open(self.path("real/t.jsonl")) as f:
            self.assertEqual(len(f.read().splitlines()), 21)
        self.assertEqual([n for n in os.listdir(self.dir) + os.listdir(
            self.path("real")) if n.startswith(".rbsim-")], [])

    def test_option_name_is_not_a_value(self):
        s = self.scene()
        r = self.rbsim("run", s, "--csv", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--csv needs a value, got the option '--quiet'", r.stderr)
        self.assertIn("./--quiet", r.stderr)
        self.assertFalse(os.path.exists(self.path("--quiet")))
        r = self.rbsim("run", s, "--steps", "5", "--csv", "./--quiet",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(self.assert_whole_frames(self.path("--quiet")), 6)

    def test_one_output_on_stdout(self):
        s = self.scene()
        for a, b in (("--csv", "--json"), ("--stats", "--json"),
                     ("--csv", "--stats")):
            r = self.rbsim("run", s, a, "-", b, "-")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("both write to standard output", r.stderr)
            self.assertEqual(r.stdout, "")

    def _interrupt(self, sig, code, existing=False, first=(), preexec=None):
        """Run a long scene, send each signal of first (the run must go on),
        then sig: the run stops with exit code, outputs whole."""
        s = self.scene()
        if existing:  # old outputs: the run writes temporaries, then renames
            for name in ("i.csv", "i.jsonl", "i_stats.csv"):
                with open(self.path(name), "w") as f:
                    f.write("OLD\n")
        p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--steps",
                              "100000", "--csv", "i.csv", "--json", "i.jsonl",
                              "--stats", "i_stats.csv"], cwd=self.dir,
                             stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True,
                             preexec_fn=preexec)
        try:
            # Wait until frames are being written, then interrupt.
            deadline = time.time() + 30
            while time.time() < deadline:
                tmp = [n for n in os.listdir(self.dir)
                       if n.startswith(".rbsim-")] if existing else ["i.csv"]
                if any(os.path.getsize(self.path(n)) > 2000 for n in tmp
                       if os.path.exists(self.path(n))):
                    break
                time.sleep(0.05)
            for f in first:
                p.send_signal(f)
                time.sleep(0.3)  # taken by the signal thread before sig
                self.assertIsNone(p.poll(), "stopped by %r" % f)
            p.send_signal(sig)
            out, err = p.communicate(timeout=30)
        finally:
            if p.poll() is None:
                p.kill()
        self.assertEqual(p.returncode, code, err)
        self.assertIn("stopped at frame", out)
        self.assertIn("by " + sig.name, out)
        n = self.assert_whole_frames(self.path("i.csv"))
        self.assertGreater(n, 2)
        self.assertLess(n, 100001)
        with open(self.path("i.jsonl")) as f:
            objs = [json.loads(l) for l in f]
        self.assertEqual([o["frame"] for o in objs], list(range(n)))
        with open(self.path("i_stats.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), n + 1)

    def test_sigint(self):
        self._interrupt(signal.SIGINT, 130)

    def test_sigterm(self):
        self._interrupt(signal.SIGTERM, 143)

    def test_signal_after_the_last_frame_was_made(self):
        # A short realtime run: the simulation makes all 30 frames at once
        # and the renderer paces them.  A signal then drops the pacing and
        # the reel is written out, so the run "completes" -- it was still
        # stopped: exit 128 + the signal and the "stopped" line (exit 0
        # and a plain summary before).
        sim = dict(SCENE["simulation"], steps=30, dt=0.02)
        s = self.scene(simulation=sim)
        for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
            p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--csv", "r.csv"],
                                 cwd=self.dir, stdin=subprocess.DEVNULL,
                                 stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True)
            try:
                deadline = time.time() + 30
                while time.time() < deadline and not (
                        os.path.exists(self.path("r.csv")) and
                        os.path.getsize(self.path("r.csv")) > 0):
                    time.sleep(0.02)
                time.sleep(0.1)
                p.send_signal(sig)
                out, err = p.communicate(timeout=30)
            finally:
                if p.poll() is None:
                    p.kill()
            self.assertEqual(p.returncode, code, (out, err))
            self.assertIn("stopped at frame", out)
            self.assertIn("by " + sig.name, out)
            self.assertEqual(self.assert_whole_frames(self.path("r.csv")), 31)

    def test_sigterm_replaces_existing_outputs(self):
        self._interrupt(signal.SIGTERM, 143, existing=True)
        self.assertEqual([n for n in os.listdir(self.dir)
                          if n.startswith(".rbsim-")], [])

    def test_outside_sigusr1_keeps_signals_working(self):
        # SIGUSR1 ends the signal thread only when rbsim asks: one from
        # outside is ignored and SIGTERM still stops the run.
        self._interrupt(signal.SIGTERM, 143, first=[signal.SIGUSR1])

    def test_sighup_stops_cleanly(self):
        # A closed terminal stops the run like SIGTERM: 128 + 1, outputs
        # whole and renamed onto the old files, no temporary left.
        def default_hup():  # as from a terminal, even if we run under nohup
            signal.signal(signal.SIGHUP, signal.SIG_DFL)

        self._interrupt(signal.SIGHUP, 129, existing=True, preexec=default_hup)
        self.assertEqual([n for n in os.listdir(self.dir)
                          if n.startswith(".rbsim-")], [])

    def test_sighup_ignored_under_nohup(self):
        def ignore_hup():
            signal.signal(signal.SIGHUP, signal.SIG_IGN)

        self._interrupt(signal.SIGTERM, 143, first=[signal.SIGHUP],
                        preexec=ignore_hup)

    def test_sigint_ignored_in_a_background_job(self):
        # A shell starts a background job with SIGINT ignored (Ctrl-C at the
        # terminal must leave it alone): the run keeps it ignored, and stops
        # on SIGTERM as always.
        def ignore_int():
            signal.signal(signal.SIGINT, signal.SIG_IGN)

        self._interrupt(signal.SIGTERM, 143, first=[signal.SIGINT],
                        preexec=ignore_int)

    def _stop_blocked(self, p, sig, blocked_for=1.0):
        """Send sig to p once it has been blocked for blocked_for seconds;
        it must end within 5 s (a regression is killed, not waited for):
        its (stdout, stderr)."""
        time.sleep(blocked_for)
        self.assertIsNone(p.poll(), "ended before the signal")
        p.send_signal(sig)
        sent = time.time()
        try:
            p.wait(timeout=5)
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()
            self.fail("still running 5 s after %s" % sig.name)
        self.assertLess(time.time() - sent, 5)
        return p.communicate(timeout=30)

    def test_signal_stops_a_fifo_without_reader(self):
        # A FIFO no one opens for reading blocks open() for ever: the signal
        # thread took SIGINT/SIGTERM but nothing woke the main thread, which
        # ran until SIGKILL.  The signal ends the run before it starts: exit
        # 128 + the signal, and like any run stopped before it starts it
        # leaves nothing (the existing stats file as it was, no temporary).
        s = self.scene()
        os.mkfifo(self.path("ff"))
        for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
            with open(self.path("old.csv"), "w") as f:
                f.write("OLD\n")
            p = subprocess.Popen([RBSIM, "run", s, "--steps", "2", "--quiet",
                                  "--stats", "old.csv", "--csv", "ff"],
                                 cwd=self.dir, stdin=subprocess.DEVNULL,
                                 stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
            out, err = self._stop_blocked(p, sig)
            self.assertEqual(p.returncode, code, err)
            self.assertIn("stopped by %s before the run started" % sig.name,
                          err)
            self.assertIn("'ff'", err)
            with open(self.path("old.csv")) as f:
                self.assertEqual(f.read(), "OLD\n")
            self.assertEqual(sorted(os.listdir(self.dir)),
                             ["ff", "old.csv", "scene.json"])

    def test_signal_stops_reading_a_scene_or_checkpoint_that_blocks(self):
        # The scene (or the --resume checkpoint) is a FIFO no one writes, or
        # a pipe whose writer stalls: the main thread blocked in open() or
        # read() while the signal thread took the signal, and only SIGKILL
        # ended the run (a probe of session 46).  Exit 128 + the signal,
        # the reading named; nothing written.
        s = self.scene()
        os.mkfifo(self.path("ff"))
        cases = [(["run", "ff"], "reading the scene 'ff'", None),
                 (["run", s, "--resume", "ff"], "reading the checkpoint 'ff'", None),
                 (["run", "/dev/stdin"], "reading the scene '/dev/stdin'", subprocess.PIPE)]
        for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
            for args, what, stdin in cases:
                p = subprocess.Popen([RBSIM] + args + ["--steps", "2", "--quiet",
                                                       "--csv", "a.csv"],
                                     cwd=self.dir, stdin=stdin,
                                     stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
                if stdin is not None:
                    p.stdin.write('{"simulation": ')  # (and then nothing)
                    p.stdin.flush()
                out, err = self._stop_blocked(p, sig)
                self.assertEqual(p.returncode, code, err)
                self.assertEqual(err, "rbsim: stopped by %s before the run started: "
                                      "while %s\n" % (sig.name, what))
                self.assertEqual(sorted(os.listdir(self.dir)), ["ff", "scene.json"])

    def test_signal_stops_a_stalled_pipe_reader(self):
        # Standard output is a pipe whose reader stopped reading (here: never
        # reads): write() blocks once the pipe is full.  SIGTERM/SIGINT stop
        # the run within seconds, exit 128 + the signal; the other output
        # (a file) holds whole frames, renamed onto the old file; a note names
        # the output cut short.  (What the pipe took cannot be taken back.)
        s = self.scene()
        for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
            with open(self.path("st.csv"), "w") as f:
                f.write("OLD\n")
            p = subprocess.Popen([RBSIM, "run", s, "--steps", "1000000",
                                  "--csv", "-", "--stats", "st.csv"],
                                 cwd=self.dir, stdin=subprocess.DEVNULL,
                                 stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE)
            out, err = self._stop_blocked(p, sig, 1.5)
            err = err.decode()
            self.assertEqual(p.returncode, code, err)
            self.assertIn("by " + sig.name, err)
            self.assertRegex(err, r"rbsim: note: csv renderer '-': frame \d+: "
                             r"write to '-' given up")
            self.assertTrue(out.startswith(CSV_HEADER.encode() + b"\n"))
            self.assertGreater(len(out), 4096)
            with open(self.path("st.csv")) as f:
                rows = f.read().splitlines()
            self.assertEqual(rows[0], STATS_HEADER)
            self.assertEqual([int(r.split(",")[0]) for r in rows[1:]],
                             list(range(len(rows) - 1)))
            self.assertEqual([n for n in os.listdir(self.dir)
                              if n.startswith(".rbsim-")], [])

    def test_file_size_limit_is_a_write_error(self):
        # Under ulimit -f with SIGXFSZ at its default (death), replacing an
        # existing file: exit 4 naming the file (not its temporary), the file
        # holds whole frames, no temporary is left.
        limit = 60000
        limit_size = file_size_limit(limit, signal.SIG_DFL)
        s = self.scene()
        with open(self.path("big.csv"), "w") as f:
            f.write("OLD\n")
        r = subprocess.run([RBSIM, "run", s, "--csv", "big.csv", "--steps",
                            "5000", "--quiet"], cwd=self.dir,
                           capture_output=True, text=True, timeout=60,
                           preexec_fn=limit_size, stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("'big.csv'", r.stderr)
        self.assertIn("File too large", r.stderr)
        self.assertNotIn(".rbsim-", r.stderr)
        self.assertEqual([n for n in os.listdir(self.dir)
                          if n.startswith(".rbsim-")], [])
        self.assertLessEqual(os.path.getsize(self.path("big.csv")), limit)
        self.assertGreater(self.assert_whole_frames(self.path("big.csv")), 10)

        # convert too: a write error, the old file kept, nothing left over.
        with open(self.path("conv.json"), "w") as f:
            f.write("OLD\n")
        before = sorted(os.listdir(self.dir))
        r = subprocess.run([RBSIM, "convert", s, "conv.json"], cwd=self.dir,
                           capture_output=True, text=True, timeout=60,
                           preexec_fn=file_size_limit(200, signal.SIG_DFL),
                           stdin=subprocess.DEVNULL)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("conv.json", r.stderr)
        self.assertIn("File too large", r.stderr)
        self.assertEqual(sorted(os.listdir(self.dir)), before)
        with open(self.path("conv.json")) as f:
            self.assertEqual(f.read(), "OLD\n")

    def _lose_outputs_mid_run(self, folder, lose):
        """A --realtime run writing FOLDER/c.csv and FOLDER/j.jsonl; once
        frames are in c.csv, lose(self) takes the outputs away.  Returns
        (exit code, stderr)."""
        s = self.scene()
        p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--steps", "1500",
                              "--quiet", "--csv", folder + "/c.csv", "--json",
                              folder + "/j.jsonl"], cwd=self.dir,
                             stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        try:
            deadline = time.time() + 30
            c = self.path(folder + "/c.csv")
            while time.time() < deadline and not (
                    os.path.exists(c) and os.path.getsize(c) > 2000):
                time.sleep(0.02)
            self.assertIsNone(p.poll(), "the run ended before the outputs were lost")
            lose(self)
            out, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        return p.returncode, err

    def test_output_folder_removed_mid_run(self):
        # rm -rf of the outputs' folder during a run: the new files were
        # written to the end into unlinked inodes and the run exited 0 with
        # nothing on disk, while an existing output (a temporary renamed at
        # the end), --png or --checkpoint reported the same loss with exit
        # 4.  At finish a dumper's file with no link left is an error naming
        # it (the first lost output is the run's error, as for write errors).
        code, err = self._lose_outputs_mid_run(
            "gone", lambda t: shutil.rmtree(t.path("gone")))
        self.assertEqual(code, 4, err)
        self.assertIn("rbsim: error: csv renderer 'gone/c.csv': 'gone/c.csv' was "
                      "removed during the run (the file or its folder): what was "
                      "written to it is lost\n", err)
        self.assertFalse(os.path.exists(self.path("gone")))

    def test_output_moved_mid_run(self):
        # The path no longer names the file written (renamed away, or
        # replaced by another file): the output is not where it was asked
        # for, also exit 4 naming the path.
        os.mkdir(self.path("kept"))

        def move(t):
            os.rename(t.path("kept/c.csv"), t.path("kept/moved.csv"))

        code, err = self._lose_outputs_mid_run("kept", move)
        self.assertEqual(code, 4, err)
        self.assertIn("rbsim: error: csv renderer 'kept/c.csv': 'kept/c.csv' was "
                      "moved or removed during the run (No such file or "
                      "directory): what was written to it is not there\n", err)

        os.mkdir(self.path("kept2"))  # (a fresh folder: kept/j.jsonl exists now)

        def replace(t):
            os.rename(t.path("kept2/j.jsonl"), t.path("kept2/moved.jsonl"))
            with open(t.path("kept2/j.jsonl"), "w") as f:
                f.write("another file\n")

        code, err = self._lose_outputs_mid_run("kept2", replace)
        self.assertEqual(code, 4, err)
        self.assertIn("rbsim: error: json renderer 'kept2/j.jsonl': 'kept2/j.jsonl' "
                      "was replaced by another file during the run: what was "
                      "written to it is not there\n", err)
        with open(self.path("kept2/j.jsonl")) as f:
            self.assertEqual(f.read(), "another file\n")  # never touched

    def test_numerical_failure_exit_4(self):
        bodies = SCENE["bodies"] + [
            {"name": "rocket", "type": "sphere", "radius": 0.1, "mass": 1,
             "position": [5, 5, 1], "force": [1e308, 0, 0]}]
        s = self.scene(bodies=bodies)
        r = self.rbsim("run", s, "--csv", "n.csv", "--steps", "100000")
        if r.returncode == 3:
            self.skipTest("the scene rejects such a force: " + r.stderr)
        self.assertEqual(r.returncode, 4, r.stdout + r.stderr)
        self.assertIn("numerical failure", r.stderr)
        self.assertIn("t = ", r.stderr)
        with open(self.path("n.csv"), "rb") as f:
            self.assertTrue(f.read().endswith(b"\n"))


class DeterminismTests(Base):
    def test_byte_identical_runs_and_renderer_counts(self):
        s = self.scene()
        outs = []
        runs = [["--csv", "one.csv"],
                ["--csv", "two.csv"],
                ["--csv", "four.csv", "--json", "x.jsonl", "--stats",
                 "x_stats.csv", "--reel", "2"]]
        s4 = self.scene("four.json",
                        renderers=[{"type": "csv", "path": "scene4.csv"}])
        for args in runs:
            r = self.rbsim("run", s, "--steps", "1500", *args)
            self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s4, "--steps", "1500", "--csv", "with4.csv",
                       "--json", "y.jsonl", "--stats", "y_stats.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        for name in ("one.csv", "two.csv", "four.csv", "with4.csv",
                     "scene4.csv"):
            with open(self.path(name), "rb") as f:
                outs.append(f.read())
        self.assertGreater(len(outs[0]), 100000)
        for o in outs[1:]:
            self.assertEqual(o, outs[0])


SUITES = {"cli": CliTests, "fault": FaultTests,
          "determinism": DeterminismTests}

if __name__ == "__main__":
    names = sys.argv[1:] or list(SUITES)
    suite = unittest.TestSuite()
    for n in names:
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(
            SUITES[n]))
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    sys.exit(0 if result.wasSuccessful() else 1)
