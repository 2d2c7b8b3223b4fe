"""The "sdl" renderer's PNG files when writes fail, through the rbsim command.

Run as: python test_sdl_cli.py, with RBSIM (the rbsim binary, built with SDL)
in the environment.  Writes fail deterministically under a file size limit
(RLIMIT_FSIZE, `ulimit -f`): a write that would make a file larger than the
limit fails with EFBIG, "File too large" (rbsim ignores SIGXFSZ itself, so
it is left at its default here, which would kill a process that did not).
The limits are taken from the sizes of the same run's files without a limit
(rendering is deterministic: same scene, same bytes), so the test does not
depend on what the PNG encoder makes of a picture.  A failed file must be
reported (exit 4, the file and the reason) and removed; every file left
must be whole, byte for byte the file of the run without a limit.
"""
import json
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time
import unittest

RBSIM = os.environ.get("RBSIM", "rbsim")

# A PNG ends with the IEND chunk: length 0, "IEND", its CRC.
IEND = b"\x00\x00\x00\x00IEND\xaeB`\x82"

STEPS = 20
SCENE = {
    "format": 1,
    "simulation": {"steps": STEPS, "dt": 0.01},
    "materials": [{"pair": ["*", "*"], "static": 0.5, "kinetic": 0.3,
                   "restitution": 0.7}],
    "bodies": [
        {"name": "floor", "type": "plane", "point": [0, 0, 0],
         "normal": [0, 0, 1], "color": "#808080", "texture": "checker"},
        {"name": "ball", "type": "sphere", "radius": 0.1, "mass": 1,
         "position": [0, 0, 1.1], "velocity": [1, 0, 0],
         "color": "#d03030", "texture": "stripes"},
    ],
}


def file_size_limit(limit):
    """A preexec_fn: files may grow to `limit` bytes, SIGXFSZ at its
    default (death, unless the program ignores it)."""
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_DFL)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return apply


def frame(k):
    return "frame_%06d.png" % k


class PngWriteErrors(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="rbsim-sdl-")
        self.dir = self._tmp.name
        self.scene = os.path.join(self.dir, "scene.json")
        with open(self.scene, "w") as f:
            json.dump(SCENE, f)
        # The run without a limit: the files every limited run is held to.
        r = self.run_png("full", None)
        if "without SDL" in r.stderr:
            self.skipTest("rbsim built without SDL")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.full = self.files("full")
        self.assertEqual(sorted(self.full),
                         ["contact_sheet.png"] +
                         [frame(k) for k in range(STEPS + 1)])

    def tearDown(self):
        self._tmp.cleanup()

    def run_png(self, folder, limit, *extra):
        return subprocess.run(
            [RBSIM, "run", self.scene, "--png", folder, "--quiet"] +
            list(extra), cwd=self.dir, stdin=subprocess.DEVNULL,
            capture_output=True, text=True, timeout=120,
            preexec_fn=None if limit is None else file_size_limit(limit))

    def files(self, folder):
        """{name: bytes} of the folder's files; each must be a whole PNG."""
        out = {}
        for name in os.listdir(os.path.join(self.dir, folder)):
            with open(os.path.join(self.dir, folder, name), "rb") as f:
                data = f.read()
            self.assertTrue(data.endswith(IEND), "%s/%s is cut short (%d "
                            "bytes)" % (folder, name, len(data)))
            out[name] = data
        return out

    def assert_failed_on(self, r, folder, name):
        """Exit 4 (a renderer failure), one message naming the file and the
        system's reason."""
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn('cannot write "%s/%s": File too large' % (folder, name),
                      r.stderr)

    def test_frame_fails_mid_run(self):
        # The first frame larger than every frame before it, k: with the
        # limit at the largest of frames 0..k-1 those are written and frame
        # k fails, so the run stops there.
        sizes = [len(self.full[frame(k)]) for k in range(STEPS + 1)]
        k = next((i for i in range(1, len(sizes))
                  if sizes[i] > max(sizes[:i])), None)
        self.assertIsNotNone(k, "no frame larger than those before it: %r"
                             % sizes)
        r = self.run_png("png", max(sizes[:k]))
        self.assert_failed_on(r, "png", frame(k))
        self.assertIn("frame %d: " % k, r.stderr)
        left = self.files("png")
        # Frames 0..k-1, byte for byte.  The contact sheet (of those k
        # frames, so not the full run's) is there if it fitted under the
        # limit; files() has checked it is whole.
        left.pop("contact_sheet.png", None)
        self.assertEqual(sorted(left), [frame(i) for i in range(k)])
        for name, data in left.items():
            self.assertEqual(data, self.full[name], name)

    def test_contact_sheet_fails(self):
        # Every frame fits, the contact sheet does not: exit 4 naming it,
        # no sheet left, the frames whole.
        biggest = max(len(d) for n, d in self.full.items()
                      if n != "contact_sheet.png")
        sheet = len(self.full["contact_sheet.png"])
        self.assertGreater(sheet, biggest, "the sheet must be the largest")
        r = self.run_png("png", biggest)
        self.assert_failed_on(r, "png", "contact_sheet.png")
        left = self.files("png")
        self.assertEqual(sorted(left), [frame(k) for k in range(STEPS + 1)])
        for name, data in left.items():
            self.assertEqual(data, self.full[name], name)

    def test_first_frame_fails(self):
        # Nothing fits: frame 0 fails, and no file is left at all (no empty
        # or cut PNG, and no contact sheet of no frames).
        r = self.run_png("png", 1000)
        self.assert_failed_on(r, "png", frame(0))
        self.assertIn("frame 0: ", r.stderr)
        self.assertEqual(self.files("png"), {})

    def test_a_users_link_is_left(self):
        # A frame's name that is the user's link to /dev/full: the write
        # fails (exit 4, named), and the link stays -- only a regular file
        # the renderer cannot write whole is removed (it unlinked whatever
        # was there: a review of session 40).
        os.mkdir(os.path.join(self.dir, "png"))
        link = os.path.join(self.dir, "png", frame(1))
        os.symlink("/dev/full", link)
        r = self.run_png("png", None)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn('cannot write "png/%s": No space left on device' % frame(1),
                      r.stderr)
        self.assertEqual(os.readlink(link), "/dev/full")

    def test_full_disk(self):
        # A full file system ("No space left on device"): each PNG is a new
        # file, so /dev/full cannot stand in; a small tmpfs can, but
        # mounting one needs root (skipped otherwise).  The frames that fit
        # are whole; the one that did not is removed, which frees its
        # space, so the contact sheet may or may not fit after it.
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs needs root")
        mnt = os.path.join(self.dir, "small")
        os.mkdir(mnt)
        size = 3 * len(self.full[frame(0)])  # room for about 3 frames
        m = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%d" % size,
                            "tmpfs", mnt], capture_output=True, text=True)
        if m.returncode != 0:
            self.skipTest("cannot mount a tmpfs: " + m.stderr.strip())
        try:
            r = self.run_png("small/png", None)
            self.assertEqual(r.returncode, 4, r.stderr)
            self.assertRegex(r.stderr, r'cannot write "small/png/'
                             r'frame_\d{6}\.png": No space left on device')
            left = self.files("small/png")
            left.pop("contact_sheet.png", None)
            self.assertGreater(len(left), 0)
            k = len(left)
            self.assertIn('"small/png/%s": No space' % frame(k), r.stderr)
            self.assertEqual(sorted(left), [frame(i) for i in range(k)])
            for name, data in left.items():
                self.assertEqual(data, self.full[name], name)
        finally:
            subprocess.run(["umount", mnt], check=True)


class PngPathChecks(unittest.TestCase):
    """A --png folder (or a scene's sdl "path") that cannot work is refused
    before anything is written: exit 2 (3 for a scene entry), and no folder
    or file left.  Only the first missing folder's parent used to be
    checked, so deeper names were found by create() once other outputs were
    made: exit 4, folders left behind."""

    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="rbsim-sdl-path-")
        self.dir = self._tmp.name
        self.long = "z" * 300

    def tearDown(self):
        self._tmp.cleanup()

    def scene(self, renderers=None):
        s = dict(SCENE, simulation={"steps": 2, "dt": 0.01})
        if renderers is not None:
            s["renderers"] = renderers
        path = os.path.join(self.dir, "scene.json")
        with open(path, "w") as f:
            json.dump(s, f)
        return "scene.json"

    def rbsim(self, *args):
        r = subprocess.run([RBSIM] + list(args), cwd=self.dir,
                           stdin=subprocess.DEVNULL, capture_output=True,
                           text=True, timeout=120)
        if "without SDL" in r.stderr:
            self.skipTest("rbsim built without SDL")
        return r

    def left(self):
        return sorted(n for n in os.listdir(self.dir) if n != "scene.json")

    def test_name_too_long_below_a_missing_folder(self):
        scene = self.scene()
        png = "x/y/" + self.long
        r = self.rbsim("run", scene, "--png", png, "--csv", "new.csv", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("300 bytes long, longer than the file system takes",
                      r.stderr)
        self.assertEqual(self.left(), [])
        # The same with x/y there already.
        os.makedirs(os.path.join(self.dir, "x", "y"))
        r = self.rbsim("run", scene, "--png", png, "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertEqual(os.listdir(os.path.join(self.dir, "x", "y")), [])

    def test_scene_entry_name_too_long(self):
        scene = self.scene([{"type": "sdl", "path": "x/y/" + self.long,
                             "window": False}])
        r = self.rbsim("check", scene)
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertIn("longer than the file system takes", r.stdout)
        r = self.rbsim("run", scene, "--quiet")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertEqual(self.left(), [])

    def test_path_too_long(self):
        png = "/".join(["d"] * 2100)
        r = self.rbsim("run", self.scene(), "--png", png, "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("path: too long", r.stderr)
        self.assertEqual(self.left(), [])

    def test_proc(self):
        if not os.path.isdir("/proc/self"):
            self.skipTest("no /proc")
        scene = self.scene()
        r = self.rbsim("run", scene, "--png", "/proc/rbsim-nope", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn('cannot create folder "/proc/rbsim-nope"', r.stderr)
        r = self.rbsim("run", scene, "--png", "/proc", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn('cannot write in folder "/proc"', r.stderr)
        scene = self.scene([{"type": "sdl", "path": "/proc/rbsim-nope/png",
                             "window": False}])
        self.assertEqual(self.rbsim("check", scene).returncode, 3)
        self.assertEqual(self.rbsim("run", scene, "--quiet").returncode, 3)

    def test_folder_through_another_outputs_file(self):
        scene = self.scene()
        for opt in ("--csv", "--json", "--stats", "--checkpoint"):
            r = self.rbsim("run", scene, "--png", "mm/a", opt, "mm", "--quiet")
            self.assertEqual(r.returncode, 2, opt + ": " + r.stderr)
            self.assertIn("runs through 'mm'", r.stderr)
            self.assertEqual(self.left(), [], opt)
        r = self.rbsim("run", scene, "--png", "./mm/a/b", "--csv", "mm",
                       "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("runs through './mm'", r.stderr)
        # Both scene entries: a scene error.
        scene = self.scene([{"type": "csv", "path": "mm"},
                            {"type": "sdl", "path": "mm/a", "window": False}])
        r = self.rbsim("check", scene)
        self.assertEqual(r.returncode, 3, r.stdout + r.stderr)
        self.assertEqual(self.rbsim("run", scene, "--quiet").returncode, 3)
        self.assertEqual(self.left(), [])

    def test_rejected_after_create_leaves_no_folder(self):
        # The scene's sdl entry is created (its folders made), then the
        # --csv output fails at its create (its header, on /dev/full): the
        # run is rejected, exit 4, and the folders are removed again.
        if not os.path.exists("/dev/full"):
            self.skipTest("no /dev/full")
        scene = self.scene([{"type": "sdl", "path": "new/deep",
                             "window": False}])
        r = self.rbsim("run", scene, "--csv", "/dev/full", "--quiet")
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn("rbsim: error: csv renderer '/dev/full': ", r.stderr)
        self.assertEqual(self.left(), [])

    def test_dash_is_not_standard_output(self):
        scene = self.scene()
        r = self.rbsim("run", scene, "--png", "-", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn('"-" would be standard output', r.stderr)
        r = self.rbsim("run", scene, "--png", "-", "--csv", "-", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn('"-" would be standard output', r.stderr)
        self.assertEqual(self.left(), [])
        r = self.rbsim("run", scene, "--png", "./-", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("frame_000000.png", os.listdir(os.path.join(self.dir, "-")))

    def test_two_sdl_outputs_message(self):
        scene = self.scene([{"type": "sdl", "path": "cam1", "window": False}])
        r = self.rbsim("run", scene, "--png", "cam1", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("two sdl outputs both write 'cam1'", r.stderr)

    def test_far_spheres_default_camera(self):
        # Spheres near +-1e100 m put the default camera (placed from their
        # bounding box) beyond 1e100 m: the run started and stopped at frame
        # 0 (exit 4, "position: not finite or beyond 1e100 m ... (from the
        # camera's place)") and check passed it (a probe of session 46).  Now
        # run and check refuse it before the run, say it is the default
        # camera and what to give instead; nothing is written.
        s = dict(SCENE, simulation={"steps": 2, "dt": 0.01, "gravity": [0, 0, 0]})
        s["bodies"] = [
            {"name": "a", "type": "sphere", "radius": 1, "mass": 1,
             "position": [1e100, 0, 0]},
            {"name": "b", "type": "sphere", "radius": 1, "mass": 1,
             "position": [-1e100, 0, 0]}]
        advice = ("view 0: position: not finite or beyond 1e100 m at frame 0 "
                  "(the default camera, placed from the spheres' bounding "
                  "box: give the view a \"position\" and a \"target\")")
        for renderers, code, extra in (
                ([{"type": "sdl", "path": "pics", "window": False}], 3, []),
                (None, 2, ["--png", "pics"])):
            s.pop("renderers", None)
            if renderers is not None:
                s["renderers"] = renderers
            with open(os.path.join(self.dir, "far.json"), "w") as f:
                json.dump(s, f)
            r = self.rbsim("run", "far.json", "--quiet", *extra)
            self.assertEqual(r.returncode, code, r.stderr)
            self.assertIn(advice, r.stderr)
            self.assertNotIn("pics", os.listdir(self.dir))
            if renderers is not None:
                r = self.rbsim("check", "far.json")
                self.assertEqual(r.returncode, 3, r.stdout)
                self.assertIn("renderers[0] (sdl): " + advice, r.stdout)
        # given a position and a target, the same spheres run
        s["renderers"] = [{"type": "sdl", "path": "pics", "window": False,
                           "camera": {"position": [0, -10, 0],
                                      "target": [0, 0, 0]}}]
        with open(os.path.join(self.dir, "far.json"), "w") as f:
            json.dump(s, f)
        r = self.rbsim("run", "far.json", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_resumed_run_checks_the_checkpoints_state(self):
        # A resumed run places the default camera at its own first frame, so
        # the check before the run must look at the checkpoint's spheres,
        # not the scene's start (a leftover named in session 47): far
        # spheres in the checkpoint are refused naming its frame, far ones
        # only at the scene's start are not.  Positions are state, so one
        # scene's checkpoint continues the other.
        def write(name, x):
            s = dict(SCENE, simulation={"steps": 3, "dt": 0.01,
                                        "gravity": [0, 0, 0]})
            s["bodies"] = [
                {"name": "a", "type": "sphere", "radius": 1, "mass": 1,
                 "position": [x, 0, 0]},
                {"name": "b", "type": "sphere", "radius": 1, "mass": 1,
                 "position": [-x, 0, 0]}]
            with open(os.path.join(self.dir, name), "w") as f:
                json.dump(s, f)
        write("far.json", 1e100)
        write("near.json", 2)
        for scene, ck in (("far.json", "far.ck"), ("near.json", "near.ck")):
            r = self.rbsim("run", scene, "--steps", "1", "--checkpoint", ck,
                           "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
        r = self.rbsim("run", "near.json", "--resume", "far.ck", "--png",
                       "pics", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("view 0: position: not finite or beyond 1e100 m at "
                      "frame 1 (the default camera", r.stderr)
        self.assertNotIn("pics", os.listdir(self.dir))
        r = self.rbsim("run", "far.json", "--resume", "near.ck", "--png",
                       "pics", "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(os.path.join(self.dir, "pics"))),
                         ["contact_sheet.png", "frame_000002.png",
                          "frame_000003.png"])

    def test_a_folder_or_fifo_at_a_frames_name_is_refused_before_the_run(self):
        # The renderer leaves names that are not regular files alone, and its
        # write of that frame failed mid-run: a folder frame_000002.png gave
        # exit 4 with the CSV cut at frame 2, a folder contact_sheet.png
        # exit 4 after the whole run, and a FIFO held the run for good (a
        # probe of session 47).  Now refused
        # before anything is written, naming the entry and the frame; a name
        # the run does not write (another --every) is no obstacle, and a
        # device or link is written as before (test_a_users_link_is_left).
        self.scene()
        pics = os.path.join(self.dir, "pics")
        os.makedirs(os.path.join(pics, "frame_000002.png"))
        r = self.rbsim("run", "scene.json", "--png", "pics", "--csv", "a.csv",
                       "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("rbsim run: --png: 'pics/frame_000002.png' is a folder, "
                      "where the run writes frame 2: move it, or name another "
                      "folder", r.stderr)
        self.assertEqual(self.left(), ["pics"])
        self.assertEqual(os.listdir(pics), ["frame_000002.png"])
        # --every 3 writes frames 0 and 3 of 3 steps, not 2
        s = dict(SCENE, simulation={"steps": 3, "dt": 0.01})
        with open(os.path.join(self.dir, "three.json"), "w") as f:
            json.dump(s, f)
        r = self.rbsim("run", "three.json", "--png", "pics", "--every", "3",
                       "--quiet")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(os.listdir(pics)),
                         ["contact_sheet.png", "frame_000000.png",
                          "frame_000002.png", "frame_000003.png"])
        # a scene entry: exit 3 at the entry
        os.rmdir(os.path.join(pics, "frame_000002.png"))
        os.makedirs(os.path.join(pics, "frame_000001.png"))
        self.scene([{"type": "sdl", "path": "pics", "window": False}])
        r = self.rbsim("run", "scene.json", "--quiet")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("renderers[0] (sdl): 'pics/frame_000001.png' is a "
                      "folder, where the run writes frame 1", r.stderr)
        # the contact sheet
        os.rmdir(os.path.join(pics, "frame_000001.png"))
        self.scene()
        os.makedirs(os.path.join(self.dir, "sheet", "contact_sheet.png"))
        r = self.rbsim("run", "scene.json", "--png", "sheet", "--quiet")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("'sheet/contact_sheet.png' is a folder, where the run "
                      "writes its contact sheet", r.stderr)
        self.assertEqual(os.listdir(os.path.join(self.dir, "sheet")),
                         ["contact_sheet.png"])
        # a FIFO: the renderer's open() waited for a reader, and SIGINT and
        # SIGTERM did not end the run (only SIGKILL did)
        os.makedirs(os.path.join(self.dir, "fifo"))
        os.mkfifo(os.path.join(self.dir, "fifo", "frame_000001.png"))
        try:
            r = subprocess.run([RBSIM, "run", "scene.json", "--png", "fifo",
                                "--quiet"], cwd=self.dir,
                               stdin=subprocess.DEVNULL, capture_output=True,
                               text=True, timeout=30)
        except subprocess.TimeoutExpired:
            self.fail("the run waited on the FIFO")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("'fifo/frame_000001.png' is a FIFO, where the run "
                      "writes frame 1", r.stderr)

    def test_a_signal_ends_a_png_write_that_blocks(self):
        # A FIFO made at a frame's name during the run (after the check
        # before it): the renderer's open() waited for a reader, and SIGINT
        # and SIGTERM did not end the run, only SIGKILL (the csv, json and
        # stats outputs were ended by the signal thread's stopper; a probe
        # of session 47).  Now the PNG files' open and writes are in the
        # same stopper: exit 128 + the signal within seconds, a note naming
        # the file, the other outputs finished.
        s = dict(SCENE, simulation={"steps": 300, "dt": 0.01})
        with open(os.path.join(self.dir, "long.json"), "w") as f:
            json.dump(s, f)
        for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
            pics = os.path.join(self.dir, "pics_%d" % code)
            p = subprocess.Popen([RBSIM, "run", "long.json", "--png", pics,
                                  "--csv", "a_%d.csv" % code, "--realtime",
                                  "--quiet"], cwd=self.dir,
                                 stdin=subprocess.DEVNULL,
                                 stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
            try:
                t0 = time.time()
                while not os.path.exists(os.path.join(pics, frame(1))):
                    if p.poll() is not None or time.time() - t0 > 20:
                        out, err = p.communicate()
                        if "without SDL" in err:
                            self.skipTest("rbsim built without SDL")
                        self.fail("no frame 1: %s" % err)
                    time.sleep(0.01)
                os.mkfifo(os.path.join(pics, frame(100)))
                while not os.path.exists(os.path.join(pics, frame(99))):
                    self.assertIsNone(p.poll(), "ended before frame 100")
                    self.assertLess(time.time() - t0, 60)
                    time.sleep(0.01)
                time.sleep(1.0)  # (blocked in open() by now)
                self.assertIsNone(p.poll(), "ended before the signal")
                p.send_signal(sig)
                sent = time.time()
                try:
                    p.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    self.fail("still running 5 s after %s" % sig.name)
                self.assertLess(time.time() - sent, 5)
            finally:
                if p.poll() is None:
                    p.kill()
                out, err = p.communicate(timeout=30)
            self.assertEqual(p.returncode, code, err)
            self.assertIn('opening "%s" given up: the run was stopped while '
                          'it blocked' % os.path.join(pics, frame(100)), err)
            with open(os.path.join(self.dir, "a_%d.csv" % code)) as f:
                text = f.read()
            self.assertTrue(text.endswith("\n"))
            self.assertIn("\n99,", text)


if __name__ == "__main__":
    loader = unittest.defaultTestLoader
    result = unittest.TextTestRunner(verbosity=2).run(unittest.TestSuite(
        [loader.loadTestsFromTestCase(PngWriteErrors),
         loader.loadTestsFromTestCase(PngPathChecks)]))
    sys.exit(0 if result.wasSuccessful() else 1)
