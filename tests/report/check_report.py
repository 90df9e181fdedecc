#!/usr/bin/env python3
"""Checks a report written by hil/report/make_report.py (docs/report.md), as the ctests hil_*_report do.

usage: check_report.py [--figures a,b,...] [--animation N] [--chromium PNG] [--copy FILE...] DIR [-- COMMAND...]

With `-- COMMAND...` empties DIR, copies each --copy FILE into it and runs the command (it must exit 0 and say where it wrote the report). Then checks that
DIR/report.html exists, holds each named figure as an inline PNG that decodes (signature, IHDR, IEND) and is the
same as DIR/fig_<name>.png, and, with --animation N, that the animation data parses as JSON with N attempts whose
frames carry both vehicles, both plates and both pole ends as finite numbers. With --chromium PNG, opens the page in
headless Chromium (Debian's chromium): its screenshot, saved to PNG, is not blank, and with --animation the player ran
in the browser (its label shows a frame's time). Prints 'N passed, M failed'.
"""

import argparse
import base64
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

passed, failed = 0, 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print(f"FAILED: {what}")
    return ok


def png_ok(data):
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return False
    pos, chunks = 8, []
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        crc = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0]
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            return False
        chunks.append(kind)
        if kind == b"IHDR":
            width, height = struct.unpack(">II", body[:8])
            if width < 100 or height < 100:
                return False
        pos += 12 + length
    return bool(chunks) and chunks[0] == b"IHDR" and chunks[-1] == b"IEND" and b"IDAT" in chunks


def chromium_command():
    for name in (os.environ.get("PA_CHROMIUM", ""), "chromium", "chromium-browser"):
        if name and shutil.which(name):
            return [shutil.which(name), "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    "--virtual-time-budget=3000"]
    return None


def check_in_chromium(page, screenshot, animation):
    """The page as a person sees it: Chromium's screenshot of the whole report is not blank, and the player ran."""
    command = chromium_command()
    if not check(command is not None, "Chromium is installed (Debian package chromium; scripts/install-deps.sh)"):
        return
    url = "file://" + os.path.abspath(page)
    # A profile of its own: two checks at once (ctest -j) must not share Chromium's profile lock.
    with tempfile.TemporaryDirectory() as profile:
        command.append("--user-data-dir=" + profile)
        shot = subprocess.run(command + ["--window-size=1280,8000", "--screenshot=" + screenshot, url],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, timeout=120)
        dom = subprocess.run(command + ["--dump-dom", url], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                             text=True, timeout=120)
    if not check(shot.returncode == 0 and os.path.isfile(screenshot), f"Chromium took a screenshot ({shot.stderr[-500:]})"):
        return
    data = open(screenshot, "rb").read()
    check(png_ok(data), f"{screenshot} is a valid PNG")
    try:
        from PIL import Image
    except ImportError:
        check(False, "python3-pil (a dependency of python3-matplotlib) reads the screenshot")
        return
    image = Image.open(screenshot).convert("RGB")
    colours = image.getcolors(maxcolors=1 << 24)
    drawn = sum(n for n, c in colours if c != (255, 255, 255)) / (image.width * image.height)
    check(len(colours) > 100 and drawn > 0.02,
          f"the screenshot is not blank ({len(colours)} colours, {100 * drawn:.1f}% of it not white)")
    if animation:
        check(dom.returncode == 0 and re.search(r"id=\"anim-label\">t = [0-9.]+ s", dom.stdout) is not None,
              "the animation player ran in Chromium (its label shows a frame's time)")


def main():
    argv = sys.argv[1:]
    command = []
    if "--" in argv:
        command = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    p = argparse.ArgumentParser()
    p.add_argument("dir")
    p.add_argument("--figures", default="")
    p.add_argument("--animation", type=int, default=0)
    p.add_argument("--copy", action="append", default=[])
    p.add_argument("--chromium", metavar="PNG", default="")
    a = p.parse_args(argv)
    if command:
        shutil.rmtree(a.dir, ignore_errors=True)
        os.makedirs(a.dir)
        for file in a.copy:
            shutil.copy(file, a.dir)
        run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        print(run.stdout[-3000:])
        check(run.returncode == 0, f"the command exited {run.returncode}")
        check("report: " in run.stdout and "report.html" in run.stdout, "the command said where the report is")
    path = os.path.join(a.dir, "report.html")
    if not check(os.path.isfile(path), f"{path} exists"):
        return 1
    text = open(path, encoding="utf-8").read()
    check("<script src" not in text and "http://" not in text and "https://" not in text,
          "the page loads nothing from elsewhere")
    for name in filter(None, a.figures.split(",")):
        m = re.search(r"<figure id='fig-" + re.escape(name) + r"'>.*?src='data:image/png;base64,([A-Za-z0-9+/=]+)'",
                      text, re.S)
        if not check(m is not None, f"figure '{name}' is in the page"):
            continue
        data = base64.b64decode(m.group(1))
        check(png_ok(data), f"figure '{name}' is a valid PNG")
        file = os.path.join(a.dir, f"fig_{name}.png")
        check(os.path.isfile(file) and open(file, "rb").read() == data, f"{file} is the page's image")
    if a.animation:
        m = re.search(r"<script type='application/json' id='animation-data'>(.*?)</script>", text, re.S)
        if check(m is not None, "the page holds the animation data"):
            try:
                anim = json.loads(m.group(1))
            except ValueError as e:
                check(False, f"the animation data parses as JSON ({e})")
                anim = []
            check(len(anim) == a.animation, f"{a.animation} attempts animated (found {len(anim)})")
            for at in anim:
                check(at["fields"] == ["t", "vehicle1", "plate1", "normal1", "vehicle2", "plate2", "normal2", "end0",
                                       "end1"], f"attempt {at.get('attempt')}: the bodies")
                frames = at["frames"]
                check(len(frames) > 50, f"attempt {at['attempt']}: {len(frames)} frames")
                check(all(len(f) == 25 and all(math.isfinite(x) for x in f) for f in frames),
                      f"attempt {at['attempt']}: every frame has 25 finite numbers")
                dt = [b[0] - a_[0] for a_, b in zip(frames, frames[1:])]
                check(all(0.015 < d < 0.025 for d in dt), f"attempt {at['attempt']}: frames at 50 Hz")
                check(at["tasks"] and all(len(t) == 3 for t in at["tasks"]), f"attempt {at['attempt']}: the tasks")
        check("anim-side" in text and "anim-top" in text and "requestAnimationFrame" in text,
              "the player draws side and top views")
    if a.chromium:
        check_in_chromium(path, a.chromium, a.animation)
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
