"""rbsim run --checkpoint / --resume and rbsim explain, driving the binary.

Run as: python test_checkpoint_cli.py SUITE  (SUITE: projector, fault), with
RBSIM set to the rbsim binary.  Checkpoints are exact: a run stopped at
frame k (by --steps, a signal, or a killed process after a periodic save)
and resumed from its checkpoint must write frames k+1..N byte for byte as an
uninterrupted run does, so the comparisons below are of bytes, with no
tolerance.
"""
import json
import os
import resource
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from test_cli import BODIES, CSV_HEADER, RBSIM, SCENE, Base  # noqa: E402

FRICTIONLESS = {
    "format": 1,
    "simulation": {"steps": 100, "dt": 0.001},
    "materials": [{"pair": ["*", "*"], "static": 0, "kinetic": 0,
                   "restitution": 1}],
    "bodies": [
        {"name": "floor", "type": "plane", "point": [0, 0, 0],
         "normal": [0, 0, 1]},
        {"name": "ball", "type": "sphere", "radius": 0.1, "mass": 1,
         "position": [0, 0, 1]},
    ],
}


def read(p):
    with open(p, "rb") as f:
        return f.read()


def csv_body(data):
    """The rows of a CSV without its header line."""
    head, _, rest = data.partition(b"\n")
    assert head.decode() == CSV_HEADER, head
    return rest


class CkptBase(Base):
    def uninterrupted(self, scene, steps):
        r = self.rbsim("run", scene, "--steps", str(steps), "--csv",
                       "full.csv", "--json", "full.jsonl", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return read(self.path("full.csv")), read(self.path("full.jsonl"))

    def resume_and_compare(self, scene, steps, first_csv, first_json, k,
                           full_csv, full_json):
        """Resume from ck.bin (at frame k): frames k+1..steps, which with the
        first run's frames 0..k equal the uninterrupted run's bytes."""
        r = self.rbsim("run", scene, "--steps", str(steps), "--resume",
                       "ck.bin", "--csv", "b.csv", "--json", "b.jsonl")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("resumed: ck.bin at frame %d" % k, r.stdout)
        b_csv = read(self.path("b.csv"))
        rows = csv_body(b_csv).splitlines()
        self.assertEqual(len(rows), (steps - k) * BODIES)
        self.assertTrue(rows[0].startswith(b"%d," % (k + 1)), rows[0])
        self.assertEqual(first_csv + csv_body(b_csv), full_csv)
        self.assertEqual(first_json + read(self.path("b.jsonl")), full_json)


class ProjectorTests(CkptBase):
    def test_steps_limited_run_then_resume(self):
        s = self.scene()
        full_csv, full_json = self.uninterrupted(s, 1000)
        r = self.rbsim("run", s, "--steps", "1000", "--stats", "full_s.csv",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "437", "--checkpoint", "ck.bin",
                       "--csv", "a.csv", "--json", "a.jsonl", "--stats",
                       "a_s.csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("checkpoint: ck.bin at frame 437", r.stdout)
        a_csv = read(self.path("a.csv"))
        self.assertEqual(len(csv_body(a_csv).splitlines()), 438 * BODIES)
        self.resume_and_compare(s, 1000, a_csv, read(self.path("a.jsonl")),
                                437, full_csv, full_json)
        # The energy and step counters of each frame agree too.
        r = self.rbsim("run", s, "--steps", "1000", "--resume", "ck.bin",
                       "--stats", "b_s.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        a_s, b_s = read(self.path("a_s.csv")), read(self.path("b_s.csv"))
        self.assertEqual(a_s + b_s.partition(b"\n")[2],
                         read(self.path("full_s.csv")))
        # The resumed run's own checkpoint ends at the scene's last step.
        r = self.rbsim("run", s, "--steps", "600", "--resume", "ck.bin",
                       "--checkpoint", "ck.bin", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "600", "--resume", "ck.bin")
        self.assertEqual(r.returncode, 2)
        self.assertIn("at step 600", r.stderr)
        self.assertIn("nothing to run", r.stderr)

    def test_resumed_status_and_summary_count_from_the_checkpoint(self):
        # A run resumed at frame 437: 'status' says frame 437 of 1000 at
        # t = 0.437 s before any frame is drawn (it said frame 0 of 563),
        # and the summary counts the run's own steps (563, not 1000; the
        # end of input resumes the run).
        s = self.scene()
        r = self.rbsim("run", s, "--steps", "437", "--checkpoint", "ck.bin",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--paused", "--steps", "1000", "--resume",
                       "ck.bin", "--csv", "r.csv",
                       stdin=None, input="status\n")
        out = r.stdout + r.stderr
        self.assertEqual(r.returncode, 0, out)
        self.assertIn("frame 437 of 1000, t = 0.437 s, paused", out)
        self.assertIn(": 563 steps (", out)
        self.assertIn("simulated 0.563 s", out)

    def test_every_k_keeps_frame_numbers(self):
        # --every 10 keeps frames 0, 10, 20, ... in both runs.
        s = self.scene()
        r = self.rbsim("run", s, "--steps", "300", "--every", "10", "--csv",
                       "full.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "120", "--every", "10",
                       "--checkpoint", "ck.bin", "--csv", "a.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "300", "--every", "10",
                       "--resume", "ck.bin", "--csv", "b.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(read(self.path("a.csv")) +
                         csv_body(read(self.path("b.csv"))),
                         read(self.path("full.csv")))

    def test_every_k_checkpoint_off_a_multiple(self):
        # A part stopped at a frame that is not a multiple of K: the first
        # part kept that frame as its last (--every 3 --steps 5 wrote
        # 0 3 5, the resumed part 6 9 10), so the parts joined had a frame
        # 5 the whole run (0 3 6 9 10) has not.  A run that saves a
        # checkpoint keeps K for its last frame too: the next part goes on
        # from it.  Also the scene's own "every" and --json.
        s = self.scene()
        r = self.rbsim("run", s, "--steps", "10", "--every", "3", "--csv",
                       "full.csv", "--json", "full.jsonl", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", s, "--steps", "5", "--every", "3",
                       "--checkpoint", "ck.bin", "--csv", "a.csv", "--json",
                       "a.jsonl", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(
            [int(x.split(b",")[0]) for x in
             csv_body(read(self.path("a.csv"))).splitlines()][::BODIES],
            [0, 3])
        r = self.rbsim("run", s, "--steps", "10", "--every", "3",
                       "--resume", "ck.bin", "--csv", "b.csv", "--json",
                       "b.jsonl", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(read(self.path("a.csv")) +
                         csv_body(read(self.path("b.csv"))),
                         read(self.path("full.csv")))
        self.assertEqual(read(self.path("a.jsonl")) + read(self.path("b.jsonl")),
                         read(self.path("full.jsonl")))
        # Without --checkpoint the run's last frame is kept, as before.
        r = self.rbsim("run", s, "--steps", "5", "--every", "3", "--csv",
                       "c.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(csv_body(read(self.path("c.csv"))).splitlines()[-1]
                        .startswith(b"5,"))

    def test_stdin_as_scene_or_checkpoint_is_not_read_as_commands(self):
        # "run /dev/stdin < scene.json" read the scene's lines again as
        # commands ("unknown command" and the command list a line), and
        # "--resume /dev/stdin < ck.bin" fed the checkpoint's bytes to the
        # command reader.  Standard input that is the scene or the
        # checkpoint (its names or the same file) is not read for commands.
        s = self.scene()
        r = self.rbsim("run", s, "--steps", "100", "--checkpoint", "ck.bin",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        cases = [(["/dev/stdin"], s, "scene"),
                 (["/dev/fd/0"], s, "scene"),
                 ([s], s, "scene"),
                 ([s, "--resume", "/dev/stdin"], self.path("ck.bin"),
                  "checkpoint"),
                 ([s, "--resume", "ck.bin"], self.path("ck.bin"),
                  "checkpoint")]
        for args, fed, what in cases:
            with open(fed, "rb") as f:
                r = self.rbsim("run", *args, "--steps", "300", "--realtime",
                               "--speed", "2", "--paused", stdin=f)
            out = r.stdout + r.stderr
            self.assertEqual(r.returncode, 0, (args, out))
            self.assertFalse("unknown command" in out, args)
            self.assertIn("note: standard input is the %s: no commands are "
                          "read from it" % what, r.stderr, args)
            self.assertIn("note: --paused is ignored", r.stderr, args)
        # Another file on standard input is still read for commands.
        with open(self.path("cmds"), "w") as f:
            f.write("frobnicate\n")
        with open(self.path("cmds"), "rb") as f:
            r = self.rbsim("run", s, "--steps", "300", "--realtime", stdin=f)
        self.assertIn("unknown command", r.stdout + r.stderr)

    def test_resume_from_a_pipe(self):
        # "cat ck.bin | rbsim run SCENE --resume /dev/stdin" failed: exit 3,
        # "input/output error: /dev/stdin: cannot read" (the load seeked to
        # find the size).  A pipe is read to its end.
        s = self.scene()
        full_csv, full_json = self.uninterrupted(s, 300)
        r = self.rbsim("run", s, "--steps", "100", "--checkpoint", "ck.bin",
                       "--csv", "a.csv", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        r = subprocess.run([RBSIM, "run", s, "--steps", "300", "--resume",
                            "/dev/stdin", "--csv", "b.csv"],
                           input=read(self.path("ck.bin")), cwd=self.dir,
                           capture_output=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(b"resumed: /dev/stdin at frame 100", r.stdout)
        self.assertEqual(read(self.path("a.csv")) +
                         csv_body(read(self.path("b.csv"))), full_csv)
        # a truncated stream says so, with its length
        r = subprocess.run([RBSIM, "run", s, "--resume", "/dev/stdin"],
                           input=read(self.path("ck.bin"))[:100],
                           cwd=self.dir, capture_output=True, timeout=120)
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn(b"truncated: 100 bytes", r.stderr)

    def test_sigint_then_resume(self):
        # Interrupted at some frame k: the CSV ends at k, the checkpoint is
        # at k, and resuming gives the rest byte for byte.
        s = self.scene()
        steps = 4000
        full_csv, full_json = self.uninterrupted(s, steps)
        p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--steps",
                              str(steps), "--checkpoint", "ck.bin", "--csv",
                              "a.csv", "--json", "a.jsonl"], cwd=self.dir,
                             stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        try:
            deadline = time.time() + 30
            while time.time() < deadline:
                if (os.path.exists(self.path("a.csv")) and
                        os.path.getsize(self.path("a.csv")) > 20000):
                    break
                time.sleep(0.05)
            p.send_signal(signal.SIGINT)
            out, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        self.assertEqual(p.returncode, 130, err)
        k = self.assert_whole_frames(self.path("a.csv")) - 1
        self.assertGreater(k, 0)
        self.assertLess(k, steps)
        self.assertIn("checkpoint: ck.bin at frame %d" % k, out)
        self.resume_and_compare(s, steps, read(self.path("a.csv")),
                                read(self.path("a.jsonl")), k, full_csv,
                                full_json)

    def test_checkpoint_every_survives_a_kill(self):
        # SIGKILL leaves the last periodic checkpoint (frame a multiple of
        # 100, written atomically): resuming from it matches the full run.
        s = self.scene()
        steps = 3000
        full_csv, full_json = self.uninterrupted(s, steps)
        p = subprocess.Popen([RBSIM, "run", s, "--realtime", "--steps",
                              str(steps), "--checkpoint", "ck.bin",
                              "--checkpoint-every", "100", "--quiet"],
                             cwd=self.dir, stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        try:
            deadline = time.time() + 30
            while time.time() < deadline and not os.path.exists(
                    self.path("ck.bin")):
                time.sleep(0.02)
            time.sleep(0.25)
            p.kill()
            p.wait(timeout=30)
        finally:
            if p.poll() is None:
                p.kill()
        self.assertTrue(os.path.exists(self.path("ck.bin")))
        # A kill that lands while a checkpoint is being written leaves that
        # write's temporary (ck.bin.tmp<pid>: SIGKILL cannot be caught), never
        # any other file, and ck.bin is still the last complete checkpoint.
        left = [n for n in os.listdir(self.dir) if ".tmp" in n]
        self.assertIn(left, ([], ["ck.bin.tmp%d" % p.pid]))
        r = self.rbsim("run", s, "--steps", str(steps), "--resume", "ck.bin",
                       "--csv", "b.csv", "--json", "b.jsonl")
        self.assertEqual(r.returncode, 0, r.stderr)
        b = csv_body(read(self.path("b.csv")))
        k = int(b.split(b",", 1)[0]) - 1
        self.assertEqual(k % 100, 0)
        self.assertGreaterEqual(k, 100)
        # The full run's frames k+1.. are the resumed ones.
        full_rows = csv_body(full_csv).splitlines(keepends=True)
        self.assertEqual(b"".join(full_rows[(k + 1) * BODIES:]), b)
        full_lines = full_json.splitlines(keepends=True)
        self.assertEqual(b"".join(full_lines[k + 1:]),
                         read(self.path("b.jsonl")))

    def test_explain(self):
        s = self.scene()
        r = self.rbsim("explain", s)
        self.assertEqual(r.returncode, 0, r.stderr)
        for line in ("world: 3 spheres (3 moving, 0 fixed), 1 plane",
                     "method: auto, dt = 0.001 s",
                     "  auto: euler, since 3 spheres move (soft from 64 on)", "stages:",
                     "  in   contacts sphere-plane",
                     "  in   contacts sphere-sphere",
                     "  in   friction, rolling and spinning resistance",
                     "  out  mutual gravity"):
            self.assertIn(line, r.stdout)
        with open(self.path("smooth.json"), "w") as f:
            json.dump(FRICTIONLESS, f)
        r = self.rbsim("explain", "smooth.json", "--method", "rk4")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("method: rk4", r.stdout)
        self.assertIn("  out  contacts sphere-sphere: fewer than two spheres",
                      r.stdout)
        self.assertIn("  out  friction, rolling and spinning resistance: no "
                      "material pair has friction", r.stdout)
        r = self.rbsim("help", "explain")
        self.assertEqual(r.returncode, 0)
        self.assertIn("usage: rbsim explain SCENE", r.stdout)
        self.assertIn("explain SCENE", self.rbsim("help").stdout)
        self.assertIn("--checkpoint FILE", self.rbsim("help", "run").stdout)

    def test_explain_errors(self):
        bad = json.loads(json.dumps(FRICTIONLESS))
        bad["bodies"][1]["radius"] = -1
        bad["simulation"]["dt"] = "x"
        with open(self.path("bad.json"), "w") as f:
            json.dump(bad, f)
        r = self.rbsim("explain", "bad.json")
        self.assertEqual(r.returncode, 3)
        self.assertIn("radius", r.stdout)
        self.assertIn("dt", r.stdout)
        self.assertNotIn("stages:", r.stdout)
        self.assertEqual(self.rbsim("explain").returncode, 2)
        self.assertEqual(self.rbsim("explain", "a", "b").returncode, 2)
        r = self.rbsim("explain", self.scene(), "--method", "leapfrog")
        self.assertEqual(r.returncode, 2)
        self.assertIn("leapfrog", r.stderr)
        r = self.rbsim("explain", "missing.json")
        self.assertEqual(r.returncode, 3)
        self.assertIn("missing.json", r.stdout)


class FaultTests(CkptBase):
    def checkpoint(self, s, steps=50):
        r = self.rbsim("run", s, "--steps", str(steps), "--checkpoint",
                       "ck.bin", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        return read(self.path("ck.bin"))

    def resume_fails(self, s, data, *words):
        with open(self.path("bad.bin"), "wb") as f:
            f.write(data)
        r = self.rbsim("run", s, "--resume", "bad.bin", "--csv", "r.csv")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("'bad.bin'", r.stderr)
        for w in words:
            self.assertIn(w, r.stderr)
        self.assertFalse(os.path.exists(self.path("r.csv")))
        return r.stderr

    def test_resume_corrupt_truncated_foreign(self):
        s = self.scene()
        good = self.checkpoint(s)
        flipped = bytearray(good)
        flipped[len(good) // 2] ^= 0x10
        self.resume_fails(s, bytes(flipped), "corrupt")
        self.resume_fails(s, good[:len(good) // 2], "corrupt")
        self.resume_fails(s, good[:7])
        self.resume_fails(s, b"")
        self.resume_fails(s, read(s), "corrupt")  # a scene is not a checkpoint
        r = self.rbsim("run", s, "--resume", "nowhere.bin")
        self.assertEqual(r.returncode, 3)
        self.assertIn("'nowhere.bin'", r.stderr)
        self.assertIn("No such file", r.stderr)

    def test_resume_other_scene(self):
        s = self.scene()
        self.checkpoint(s)
        bodies = json.loads(json.dumps(SCENE["bodies"]))
        bodies[2]["name"] = "bee"
        other = self.scene("other.json", bodies=bodies)
        r = self.rbsim("run", other, "--resume", "ck.bin")
        self.assertEqual(r.returncode, 3)
        self.assertIn("does not continue the scene", r.stderr)

        self.assertIn("body slot 2", r.stderr)
        self.assertIn("'bee'", r.stderr)
        r = self.rbsim("run", s, "--dt", "0.002", "--resume", "ck.bin")
        self.assertEqual(r.returncode, 3)
        self.assertIn("time step", r.stderr)
        r = self.rbsim("run", s, "--method", "rk4", "--resume", "ck.bin")
        self.assertEqual(r.returncode, 3)
        self.assertIn("method", r.stderr)

    def test_resume_other_materials_or_settings(self):
        """A scene whose friction, restitution, material names or world
        settings changed since the checkpoint is refused, naming the
        difference: resuming would silently run the old values."""
        s = self.scene()
        self.checkpoint(s)
        mats = json.loads(json.dumps(SCENE["materials"]))
        mats[0]["kinetic"] = 0.25
        cases = [
            (self.scene("kin.json", materials=mats),
             ["material pair '*' / '*'", "mu_k 0.3 ",
              "mu_k 0.25"]),
            (self.scene("two.json", materials=SCENE["materials"] + [
                {"pair": ["rubber", "*"], "static": 0.5, "kinetic": 0.3}]),
             ["capacity max_pairs: the scene has 2, the checkpoint 1"]),
            (self.scene("e.json", simulation=dict(SCENE["simulation"],
                                                  restitution=0.9)),
             ["restitution: the scene has 0.9, the checkpoint 0.5"]),
            (self.scene("gm.json", simulation=dict(SCENE["simulation"],
                                                   gravity_mode="force")),
             ["gravity_mode: the scene has force, the checkpoint "
              "acceleration"]),
            # as the scene says them, not as the world keeps them: a row
            # without restitution takes the simulation's (kept as -1), a
            # switch is true or false
            (self.scene("noe.json", materials=[
                {"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3}]),
             ["e (the simulation's)", "e 0.7"]),
            (self.scene("mg.json", simulation=dict(SCENE["simulation"],
                                                   mutual_gravity={"G": 6.674e-11})),
             ["mutual_gravity: the scene has true, the checkpoint false"]),
        ]
        for scene, words in cases:
            r = self.rbsim("run", scene, "--resume", "ck.bin", "--csv",
                           "r.csv")
            self.assertEqual(r.returncode, 3, (scene, r.stderr))
            self.assertIn("does not continue the scene", r.stderr)
            for w in words:
                self.assertIn(w, r.stderr)
            self.assertFalse(os.path.exists(self.path("r.csv")))

    def test_bad_checkpoint_paths_write_nothing(self):
        s = self.scene()
        os.mkdir(self.path("adir"))
        for path, why in (("no/such/ck.bin", "does not exist"),
                          ("adir", "not a regular file"),
                          ("adir/", "not a regular file"),
                          ("scene.json", "overwrite the scene"),
                          ("o.csv", "also the csv output")):
            r = self.rbsim("run", s, "--csv", "o.csv", "--checkpoint", path)
            self.assertEqual(r.returncode, 2, path + ": " + r.stderr)
            self.assertIn(why, r.stderr)
            self.assertFalse(os.path.exists(self.path("o.csv")), path)
        r = self.rbsim("run", s, "--checkpoint-every", "10")
        self.assertEqual(r.returncode, 2)
        self.assertIn("needs --checkpoint", r.stderr)
        r = self.rbsim("run", s, "--checkpoint", "c", "--checkpoint-every", "0")
        self.assertEqual(r.returncode, 2)
        r = self.rbsim("run", "--checkpoint", "c")
        self.assertEqual(r.returncode, 2)
        self.assertIn("need a SCENE", r.stderr)
        # A scene error writes no checkpoint either.
        bad = self.scene("bad.json", simulation={"steps": -1})
        r = self.rbsim("run", bad, "--checkpoint", "ck.bin")
        self.assertEqual(r.returncode, 3)
        self.assertFalse(os.path.exists(self.path("ck.bin")))

    def test_checkpoint_is_not_where_stdout_goes(self):
        # The file standard output is redirected to counts as '-': a
        # checkpoint onto it replaced the file by rename, and the CSV or the
        # summary printed there was lost (exit 0).  Refused before the run.
        s = self.scene()
        for name, args in (("so4.ck", ["--csv", "-", "--quiet"]),
                           ("/dev/stdout", ["--csv", "-"]),
                           ("so3.ck", [])):
            out = self.path("so5" if name.startswith("/") else name)
            with open(out, "w") as f:
                r = subprocess.run([RBSIM, "run", s, "--checkpoint", name] + args,
                                   stdin=subprocess.DEVNULL, stdout=f,
                                   stderr=subprocess.PIPE, text=True,
                                   cwd=self.dir, timeout=120)
            self.assertEqual(r.returncode, 2, (name, r.stderr))
            self.assertIn("--checkpoint '%s' is the file standard output is "
                          "redirected to" % name, r.stderr)
            self.assertIn("the csv output '-'" if args else "the summary",
                          r.stderr)
            self.assertEqual(os.path.getsize(out), 0, name)

    def test_checkpoint_path_checked_before_the_run(self):
        """A --checkpoint that cannot be written (a name too long for the
        file system, a folder that takes no files) is refused up front with
        exit 2, before any output is written, not after the whole run."""
        s = self.scene()
        for path in ("c" * 300 + ".bin", "/proc/rbsim-no-such.bin"):
            r = self.rbsim("run", s, "--csv", "o.csv", "--checkpoint", path)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("rbsim run: --checkpoint '%s'" % path, r.stderr)
            self.assertFalse(os.path.exists(self.path("o.csv")))
        self.assertEqual(os.listdir(self.dir), ["scene.json"])

    def test_checkpoint_through_a_symlink(self):
        """--checkpoint onto a symlink writes the link's target (the link
        stays), like every other output."""
        s = self.scene()
        os.mkdir(self.path("real"))
        os.symlink("real/ck.bin", self.path("link.bin"))
        r = self.rbsim("run", s, "--steps", "50", "--checkpoint", "link.bin",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(os.path.islink(self.path("link.bin")))
        self.assertEqual(os.listdir(self.path("real")), ["ck.bin"])
        r = self.rbsim("run", s, "--steps", "60", "--resume", "real/ck.bin",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_outputs_never_overwrite_the_resumed_checkpoint(self):
        s = self.scene()
        good = self.checkpoint(s)
        for opt in ("--csv", "--json", "--stats"):
            for name in ("ck.bin", "./ck.bin"):
                r = self.rbsim("run", s, "--resume", "ck.bin", opt, name)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn("would overwrite the --resume checkpoint",
                              r.stderr)
                self.assertEqual(read(self.path("ck.bin")), good)

    def test_resume_a_folder(self):
        s = self.scene()
        os.mkdir(self.path("adir"))
        r = self.rbsim("run", s, "--resume", "adir")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("adir: is a folder", r.stderr)
        self.assertNotIn("memory", r.stderr)

    def test_other_format_version_names_both(self):
        # README.md: a checkpoint of another format version is refused with
        # both versions named.  It also said "(now 10)" while the library
        # wrote 12: any version the README names must be the library's.
        import re
        import struct
        s = self.scene()
        self.checkpoint(s)
        with open(self.path("ck.bin"), "r+b") as f:
            f.seek(8)  # after the 8-byte magic: the version (native order)
            (version,) = struct.unpack("=I", f.read(4))
            f.seek(8)
            f.write(struct.pack("=I", version + 1))
        r = self.rbsim("run", s, "--resume", "ck.bin", "--csv", "r.csv")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("format version %d, this library reads version %d"
                      % (version + 1, version), r.stderr)
        self.assertFalse(os.path.exists(self.path("r.csv")))
        top = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
        with open(os.path.join(top, "README.md")) as f:
            readme = " ".join(f.read().split())
        self.assertIn("a checkpoint of another format version", readme)
        for named in re.findall(r"another format version \(now (\d+)\)", readme):
            self.assertEqual(int(named), version, "README.md names version "
                             + named)

    def test_resume_other_body_definitions(self):
        """A body whose definition changed since the checkpoint (not its
        state) is refused, naming the body and the field: resuming would
        silently run the old body."""
        s = self.scene()
        self.checkpoint(s)
        cases = [
            (2, "radius", 0.12, "radius: the scene has 0.12 m"),
            (1, "mass", 2, "mass: the scene has 2 kg, the checkpoint 1 kg"),
            (1, "fixed", True, "fixed: the scene has true"),
            (3, "force", [1, 0, 0], "force: the scene has [1, 0, 0]"),
            (3, "torque", [0, 0, 1], "torque: the scene has [0, 0, 1]"),
            (0, "normal", [0, 1, 1], "normal: the scene has"),
            (0, "point", [0, 0, -1], "point: the scene has [0, 0, -1]"),
            # the mass distribution (inertia 2/5 m r^2 -> 2/3 m r^2 for
            # hollow; an offset centre of mass) and the look
            (2, "inertia", "hollow", "inertia (about the centre of mass"),
            (2, "center_of_mass", [0.01, 0, 0],
             "center_of_mass: the scene has [0.01, 0, 0], the checkpoint [0, 0, 0]"),
            (3, "color", "#00ff00", "color: the scene has #00ff00"),
            (3, "texture", "none",
             "texture: the scene has none, the checkpoint stripes"),
        ]
        names = ["floor", "a", "b", "c"]
        for i, key, value, words in cases:
            bodies = json.loads(json.dumps(SCENE["bodies"]))
            bodies[i][key] = value
            if key == "fixed":
                bodies[i]["velocity"] = [0, 0, 0]  # (a fixed sphere's must be)
            e = self.scene("e.json", bodies=bodies)
            r = self.rbsim("run", e, "--resume", "ck.bin", "--csv", "r.csv")
            self.assertEqual(r.returncode, 3, (key, r.stderr))
            self.assertIn("does not continue the scene", r.stderr)
            self.assertIn("body '%s' (slot %d)" % (names[i], i), r.stderr)
            self.assertIn(words, r.stderr)
            self.assertFalse(os.path.exists(self.path("r.csv")))
        # Only the state differs: accepted.
        bodies = json.loads(json.dumps(SCENE["bodies"]))
        bodies[1]["position"] = [0.2, 0, 0.5]
        e = self.scene("e.json", bodies=bodies)
        r = self.rbsim("run", e, "--resume", "ck.bin", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_checkpoint_write_fails_mid_run(self):
        # A file size limit below a checkpoint's size: the first periodic
        # save (frame 50) fails.  The run stops with exit 4 naming the file;
        # the CSV (on a pipe, which the limit does not touch) holds whole
        # frames 0..50.
        s = self.scene()
        size = len(self.checkpoint(s, 1))
        os.remove(self.path("ck.bin"))

        def limit_size():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (size // 2, size // 2))

        r = subprocess.run([RBSIM, "run", s, "--steps", "300", "--csv", "-",
                            "--checkpoint", "ck.bin", "--checkpoint-every",
                            "50"], cwd=self.dir, capture_output=True,
                           timeout=120, preexec_fn=limit_size,
                           stdin=subprocess.DEVNULL)
        err = r.stderr.decode()
        self.assertEqual(r.returncode, 4, err)
        self.assertIn("cannot save the checkpoint 'ck.bin' at frame 50", err)
        self.assertIn("File too large", err)
        self.assertFalse(os.path.exists(self.path("ck.bin")))
        self.assertEqual([n for n in os.listdir(self.dir) if ".tmp" in n], [])
        rows = csv_body(r.stdout).decode().splitlines()
        self.assertEqual(len(rows), 51 * BODIES)
        self.assertTrue(rows[-1].startswith("50,"))


SUITES = {"projector": ProjectorTests, "fault": FaultTests}

if __name__ == "__main__":
    names = sys.argv[1:] or list(SUITES)
    suite = unittest.TestSuite()
    for n in names:
        suite.addTests(unittest.defaultTestLoader.loadTestsFromTestCase(
            SUITES[n]))
    result = unittest.TextTestRunner(verbosity=2).run(suite)
    sys.exit(0 if result.wasSuccessful() else 1)
