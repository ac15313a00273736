"""GUI test: a user's session in the real `paraview` executable under Xvfb,
driven with xdotool (X events: key presses and mouse clicks). ParaView starts
with the plugin auto-loaded (PV_PLUGIN_PATH) and cone20Ma2p5.vtu opened
(--data); the test clicks Apply for the reader, takes Filters > Adaptive
Redistribution > Adapt To Shocks from the menu (or, with `quicklaunch`, from
the quick-launch: Ctrl+Space, "Adapt To Shocks", Enter), clicks Apply with no
property changed, waits for the filter, colours the adapted mesh by Region
from the toolbar's colour combo box, takes a screenshot of the screen
(ImageMagick's import) and saves the adapted mesh with File > Save Data
(Ctrl+S, a file name typed into ParaView's file dialog, which opens in
paraview's working directory, then OK in Configure Writer).

Then it checks the legacy .vtk the GUI wrote (more than 50,000 points from the
15,746 nodes in, a Region array with kept and new cells that match the
filter's KeptCells / NewCells field data, NumberOfSurfaces >= 1: the output
of AdaptToShocks) and the screenshot (not blank: many colours, a plausible
fraction of the render view not background, both Region colours visible:
blue kept cells and red new cells).

    pvpython RunGUIAdaptToShocks.py [menu|quicklaunch]

The buttons are found in the screenshots, not at fixed coordinates: the
Apply button by its green (ParaView paints it green while there is something
to apply), the colour combo box by its "Solid Color" icon. The menu is walked
with the keyboard (Alt+L opens Filters; Adaptive Redistribution is the fifth
entry below Search...: Recent, Favorites, Alphabetical, AMR, Adaptive
Redistribution, in a session without settings, --dr). The test ends within
120 s; Xvfb and paraview (each in its own process group) are killed at the
end whatever happened. Outputs in AR_TEST_OUTPUT_DIR: GUIAdaptToShocks_<mode>
.png (the screenshot), .vtk (what the GUI saved), .log (paraview's output),
_failure.png (the screen when a GUI step failed)."""
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import time

import numpy as np

import artest
from artest import check, say

START = time.monotonic()
DEADLINE = START + 95  # GUI steps; killing, reading and checking the results take at most ~15 s more (budget 120 s)

mode = sys.argv[1] if len(sys.argv) > 1 else "menu"
if mode not in ("menu", "quicklaunch"):
    say("usage: pvpython RunGUIAdaptToShocks.py [menu|quicklaunch]")
    sys.exit(2)
if not artest.PLUGIN or not os.path.exists(artest.PLUGIN):
    say("AR_PLUGIN does not name the built plugin: %r" % artest.PLUGIN)
    sys.exit(2)

XVFB = artest.require_program("Xvfb", "xvfb")
PARAVIEW = artest.require_program("paraview", "paraview")
XDOTOOL = artest.require_program("xdotool", "xdotool")
IMPORT = artest.require_program("import", "imagemagick")

DATA = artest.data("cone20Ma2p5.vtu")
INPUT_NODES = 15746
stem = os.path.join(os.path.abspath(artest.OUTPUT_DIR), "GUIAdaptToShocks_%s" % mode)
png, vtu, log, failure_png = stem + ".png", stem + ".vtk", stem + ".log", stem + "_failure.png"
for f in (png, vtu, log, failure_png):
    if os.path.exists(f):
        os.remove(f)
# paraview's working directory, where its file dialog opens: empty, so that
# the dialog's completer has nothing to complete while the file name is typed
# (a typed path with slashes gets mangled by its directory completion).
workdir = stem + "_cwd"
shutil.rmtree(workdir, ignore_errors=True)
os.makedirs(workdir)
# The legacy .vtk format: the XML writer's default (raw appended data) is
# what Debian's ParaView 5.11 cannot always read back (its XML parser stops
# in the binary block, depending on the bytes: it did on a fresh machine).
SAVE_NAME = "adapted.vtk"
WIDTH, HEIGHT = 1280, 1024
BACKGROUND = np.array([82, 87, 110])  # ParaView 5.11's default render view background


class GUIStepFailed(Exception):
    pass


def remaining():
    return DEADLINE - time.monotonic()


env = artest.child_environment()
for k in ("WAYLAND_DISPLAY", "QT_QPA_PLATFORM", "PV_PLUGIN_CONFIG_FILE"):
    env.pop(k, None)
env["PV_PLUGIN_PATH"] = os.path.dirname(os.path.abspath(artest.PLUGIN))


def xdo(*args, timeout=10):
    """Runs xdotool on the test's display; returns its stdout."""
    try:
        r = subprocess.run([XDOTOOL] + [str(a) for a in args], env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True, timeout=max(1.0, min(timeout, remaining())))
    except subprocess.TimeoutExpired:
        raise GUIStepFailed("xdotool %s: no answer within %.0f s" % (" ".join(map(str, args)), timeout))
    if r.returncode != 0:
        raise GUIStepFailed("xdotool %s failed (%d): %s" % (" ".join(map(str, args)), r.returncode, r.stderr.strip()))
    return r.stdout


def wait_window(name_regex, timeout):
    """The id of the first visible window whose title matches (xdotool search --sync)."""
    try:
        out = xdo("search", "--sync", "--onlyvisible", "--name", name_regex, timeout=timeout)
    except GUIStepFailed:
        raise GUIStepFailed("no window named /%s/ within %.0f s" % (name_regex, timeout))
    return out.split()[0]


def wait_focus(window, timeout=10):
    """Waits until `window` has the keyboard focus: a dialog is visible a
    moment before Qt gives it the focus, and the keys typed in between go
    elsewhere (without a window manager, to the window under the pointer)."""
    end = time.monotonic() + min(timeout, remaining())
    while xdo("getwindowfocus").strip() != window:
        if time.monotonic() > end:
            raise GUIStepFailed("window %s did not get the keyboard focus within %.0f s" % (window, timeout))
        time.sleep(0.1)
    time.sleep(0.3)


def visible_windows():
    """{id: title} of the visible windows."""
    r = subprocess.run([XDOTOOL, "search", "--onlyvisible", "--name", "."], env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.DEVNULL, text=True, timeout=10)
    titles = {}
    for w in r.stdout.split():
        t = subprocess.run([XDOTOOL, "getwindowname", w], env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.DEVNULL, text=True, timeout=10)
        titles[w] = t.stdout.strip()
    return titles


def window_gone(window, timeout):
    end = time.monotonic() + min(timeout, remaining())
    while time.monotonic() < end:
        if window not in visible_windows():
            return True
        time.sleep(0.2)
    return False


def screenshot(path):
    """The screen as an (HEIGHT, WIDTH, 3) int array, top row first; also saved as `path`."""
    try:
        r = subprocess.run([IMPORT, "-window", "root", "-depth", "8", "PNG24:" + path], env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=20)
    except subprocess.TimeoutExpired:
        raise GUIStepFailed("import (the screenshot) took more than 20 s")
    if r.returncode != 0 or not os.path.exists(path):
        raise GUIStepFailed("import failed (%d): %s" % (r.returncode, r.stdout.strip()))
    return read_png(path)


def read_png(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    w, h, _ = r.GetOutput().GetDimensions()
    a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars())
    return a.reshape(h, w, -1)[::-1, :, :3].astype(int)


def box_best(mask, bh, bw):
    """(count, x, y): the bh x bw box of `mask` with the most True pixels, and its centre."""
    s = np.zeros((mask.shape[0] + 1, mask.shape[1] + 1), dtype=np.int64)
    s[1:, 1:] = mask.cumsum(axis=0).cumsum(axis=1)
    count = s[bh:, bw:] - s[:-bh, bw:] - s[bh:, :-bw] + s[:-bh, :-bw]
    y, x = np.unravel_index(np.argmax(count), count.shape)
    return int(count[y, x]), int(x + bw // 2), int(y + bh // 2)


def apply_button(img):
    """The centre of the green (enabled) Apply button, or None: the 48 x 12
    box with the most of its light green; toolbar icons (up to 24 px) cannot
    fill such a box. The status bar (the bottom 60 rows) is left out: its
    memory gauge is the same green, as wide as the memory in use."""
    top = img[:-60]
    r, g, b = top[..., 0], top[..., 1], top[..., 2]
    green = (g > r + 25) & (g > b + 25) & (g > 150) & (np.abs(r - b) < 25)
    count, x, y = box_best(green, 12, 48)
    return (x, y) if count > 0.6 * 12 * 48 else None


def solid_color_icon(img):
    """The centre of the toolbar colour combo box's "Solid Color" icon (an
    orange ball) in the toolbars (top 160 rows), or None."""
    top = img[:160]
    orange = np.abs(top - np.array([197, 129, 62])).sum(axis=2) < 40
    count, x, y = box_best(orange, 10, 10)
    return (x, y) if count >= 8 else None


def render_view(img):
    """The render view's rectangle (x0, x1, y0, y1): the bounding box of its background colour."""
    ys, xs = np.nonzero((img == BACKGROUND).all(axis=2))
    if len(xs) < 10000:
        return None
    return xs.min(), xs.max() + 1, ys.min(), ys.max() + 1


def region_pixels(view):
    """(red, blue): the pixels of Region = 1 (new cells, red end of Cool to
    Warm) and Region = 0 (kept, blue end) in the render view."""
    r, g, b = view[..., 0], view[..., 1], view[..., 2]
    red = np.count_nonzero((r > 110) & (g < 60) & (b < 70))
    blue = np.count_nonzero((b > 120) & (r < 90) & (g < 110))
    return red, blue


def poll(what, test, timeout, interval=0.5):
    """Screenshots until test(img) gives a value other than None/False; returns (value, img)."""
    end = time.monotonic() + min(timeout, remaining())
    shot = stem + "_poll.png"
    while True:
        img = screenshot(shot)
        value = test(img)
        if value is not None and value is not False:
            return value, img
        if time.monotonic() > end:
            raise GUIStepFailed("%s: not seen within %.0f s" % (what, timeout))
        time.sleep(interval)


def poll_steady(what, test, timeout):
    """As poll, until test gives the same value in two screenshots in a row
    (the layout has settled: no button found just before it moves)."""
    previous = [None]

    def steady(img):
        value = test(img)
        same = value is not None and value == previous[0]
        previous[0] = value
        return value if same else None

    return poll(what, steady, timeout)


def click(xy):
    xdo("mousemove", xy[0], xy[1], "click", "1")  # (mousemove --sync waits forever when the pointer is already there)


def kill_group(proc, name):
    if proc is None or proc.poll() is not None:
        return
    for sig, wait in ((signal.SIGTERM, 3), (signal.SIGKILL, 3)):
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            return
        try:
            proc.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            pass
    say("     could not kill %s (pid %d)" % (name, proc.pid))


def start_xvfb():
    """Xvfb on the first free display (-displayfd): (process, ":N")."""
    rfd, wfd = os.pipe()
    proc = subprocess.Popen([XVFB, "-displayfd", str(wfd), "-screen", "0", "%dx%dx24" % (WIDTH, HEIGHT),
                             "-nolisten", "tcp", "-noreset"], pass_fds=(wfd,), stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    os.close(wfd)
    text = b""
    end = time.monotonic() + 15
    while not text.endswith(b"\n") and time.monotonic() < end:
        ready, _, _ = select.select([rfd], [], [], 0.5)
        if ready:
            chunk = os.read(rfd, 64)
            if not chunk:
                break
            text += chunk
    os.close(rfd)
    if not text.strip().isdigit():
        kill_group(proc, "Xvfb")
        raise GUIStepFailed("Xvfb did not start (it printed %r for its display)" % text)
    return proc, ":" + text.decode().strip()


def wait_file_written(path, timeout):
    """Waits until the GUI's writer has finished `path`: an XML file's closing
    tag at its end, a legacy file's size steady over two seconds."""
    end = time.monotonic() + min(timeout, remaining())
    sizes = []
    while time.monotonic() < end:
        if os.path.exists(path):
            size = os.path.getsize(path)
            sizes.append(size)
            if size > 100 and sizes[-3:] == [size] * 3 and len(sizes) >= 3:
                if not path.endswith((".vtu", ".vtm", ".vtp")):
                    return True
                with open(path, "rb") as f:
                    f.seek(size - 64)
                    if b"</VTKFile>" in f.read():
                        return True
        time.sleep(1.0)
    return False


xvfb = paraview = None
stats = {}
steps = []


def step(text):
    steps.append(text)
    say("     %5.1f s  %s" % (time.monotonic() - START, text))


try:
    xvfb, display = start_xvfb()
    env["DISPLAY"] = display
    cmd = [PARAVIEW, "--dr", "--data=" + DATA]
    step("Xvfb on %s; $ PV_PLUGIN_PATH=%s %s" % (display, env["PV_PLUGIN_PATH"], " ".join(cmd)))
    with open(log, "w") as out:
        paraview = subprocess.Popen(cmd, env=env, cwd=workdir, stdin=subprocess.DEVNULL, stdout=out,
                                    stderr=subprocess.STDOUT, start_new_session=True)
    main = wait_window("^ParaView [0-9]", 40)
    xdo("windowmove", main, 0, 0)
    xdo("windowsize", main, WIDTH, HEIGHT)  # a user maximizing it (there is no window manager)
    end = time.monotonic() + 10
    while "Geometry: %dx%d" % (WIDTH, HEIGHT) not in xdo("getwindowgeometry", main):
        if time.monotonic() > end:
            raise GUIStepFailed("the main window did not take the screen's size")
        time.sleep(0.2)
    step("main window %s, resized to the screen" % main)

    apply_xy, _ = poll_steady("the green Apply button of the reader", apply_button, 30)
    step("reader's Apply button at %s: click" % (apply_xy,))
    click(apply_xy)
    poll("the reader applied (Apply no longer green)", lambda img: apply_button(img) is None, 30)
    step("reader applied")

    xdo("windowfocus", "--sync", main)
    if mode == "menu":
        xdo("key", "alt+l")  # the Filters menu; Search... is highlighted
        time.sleep(0.5)
        xdo("key", "--delay", "80", "Down", "Down", "Down", "Down", "Down", "Right")  # Adaptive Redistribution >
        time.sleep(0.5)
        xdo("key", "Return")  # its first entry: Adapt To Shocks
        step("Filters > Adaptive Redistribution > Adapt To Shocks (Alt+L, 5 x Down, Right, Enter)")
    else:
        xdo("key", "ctrl+space")
        wait_focus(wait_window("^Dialog$", 10))
        xdo("type", "--delay", "40", "Adapt To Shocks")
        time.sleep(0.5)
        xdo("key", "Return")
        step("quick launch: Ctrl+Space, \"Adapt To Shocks\", Enter")

    apply_xy, _ = poll_steady("the green Apply button of Adapt To Shocks", apply_button, 20)
    step("Adapt To Shocks's Apply button at %s: click (no property changed)" % (apply_xy,))
    t_apply = time.monotonic()
    click(apply_xy)
    icon_xy, _ = poll_steady("Adapt To Shocks finished (Apply grey, the output shown in Solid Color)",
                             lambda img: solid_color_icon(img) if apply_button(img) is None else None, 70)
    stats["seconds"] = time.monotonic() - t_apply
    step("Adapt To Shocks finished and shown after %.1f s" % stats["seconds"])

    def coloured(img):
        view = render_view(img)
        return view if view is not None and min(region_pixels(img[view[2]:view[3], view[0]:view[1]])) > 1000 else None

    for attempt in range(3):  # a key typed before the list has the keyboard is lost: choose again
        click(icon_xy)  # opens the colour combo box's list
        time.sleep(0.8)
        xdo("type", "--delay", "40", "Region")  # the list's keyboard search
        time.sleep(0.3)
        xdo("key", "Return")
        try:
            poll("the adapted mesh coloured by Region", coloured, 10)
            break
        except GUIStepFailed:
            if attempt == 2:
                raise
            step("not coloured by Region yet: choosing again")
            xdo("key", "Escape")
            icon_xy, _ = poll("the colour combo box", solid_color_icon, 10)
    time.sleep(1.0)  # the colour legend
    screenshot(png)
    step("coloured by Region (toolbar combo box); screenshot %s" % png)

    xdo("windowfocus", "--sync", main)
    xdo("key", "ctrl+s")  # File > Save Data...
    wait_focus(wait_window("^Save File", 15))
    xdo("key", "ctrl+a")
    xdo("type", "--delay", "40", SAVE_NAME)  # in the dialog's directory: paraview's working directory
    time.sleep(0.3)
    xdo("key", "Return")
    writer = wait_window("^Configure Writer", 15)
    step("File > Save Data: typed %s; %s" % (SAVE_NAME, xdo("getwindowname", writer).strip()))
    wait_focus(writer)
    xdo("key", "Return")  # OK
    if not window_gone(writer, 10):
        raise GUIStepFailed("the Configure Writer dialog did not close on Enter")
    saved = os.path.join(workdir, SAVE_NAME)
    if not wait_file_written(saved, 40):
        raise GUIStepFailed("ParaView did not write %s within 40 s (in %s: %s)" % (saved, workdir, os.listdir(workdir)))
    os.replace(saved, vtu)
    step("the GUI wrote %s (%.1f MB), moved to %s" % (saved, os.path.getsize(vtu) / 1e6, vtu))

    stats["windows"] = sorted(visible_windows().values())
    xdo("windowfocus", "--sync", main)
    xdo("key", "ctrl+q")  # File > Exit
    try:
        paraview.wait(timeout=max(1.0, min(10, remaining())))
        step("paraview quit on Ctrl+Q (code %d)" % paraview.returncode)
    except subprocess.TimeoutExpired:
        step("paraview did not quit on Ctrl+Q within 10 s: killed")
except Exception as e:  # GUIStepFailed, or a child program that hung or could not run
    check(False, "GUI: %s%s (after: %s)" % ("" if isinstance(e, GUIStepFailed) else type(e).__name__ + ": ", e,
                                            steps[-1] if steps else "nothing"))
    try:
        if "DISPLAY" in env:
            screenshot(failure_png)
            say("     the screen at the failure: %s" % failure_png)
    except Exception:
        pass
finally:
    kill_group(paraview, "paraview")
    kill_group(xvfb, "Xvfb")
    if os.path.exists(stem + "_poll.png"):
        os.remove(stem + "_poll.png")
    if os.path.isdir(workdir) and not os.listdir(workdir):
        os.rmdir(workdir)  # what the GUI left in it otherwise stays, to be looked at

if os.path.exists(log):
    text = open(log, errors="replace").read()
    say("     paraview's output (end): " + text[-1500:].strip().replace("\n", "\n     "))
    errors = [line for line in text.splitlines() if re.search(r"\bERROR\b|ERR\||Traceback", line)]
    check(not errors, "paraview printed no error (%d error lines%s)"
          % (len(errors), (": " + errors[0].strip()) if errors else ""))
if "windows" in stats:
    # ParaView opens the Output Messages window on any error or warning.
    others = [t for t in stats["windows"] if not re.match(r"ParaView [0-9]", t)]
    check(not others, "at the end only the main window is open, no Output Messages (%s)" % ", ".join(stats["windows"]))

check(os.path.exists(vtu), "the GUI saved the adapted mesh (File > Save Data)")
if os.path.exists(vtu):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader
    r = vtkUnstructuredGridReader()
    r.SetFileName(vtu)
    r.ReadAllFieldsOn()
    r.Update()
    grid = r.GetOutput()
    n_points, n_cells = grid.GetNumberOfPoints(), grid.GetNumberOfCells()
    check(n_points > 50000, "saved mesh: %d points > 50,000 (the input: %d nodes)" % (n_points, INPUT_NODES))
    fd = grid.GetFieldData()

    def field_value(name):
        a = fd.GetAbstractArray(name)
        return None if a is None else a.GetVariantValue(0).ToString()

    region = grid.GetCellData().GetArray("Region")
    check(region is not None, "saved mesh has the cell array Region")
    if region is not None:
        counts = np.bincount(vtk_to_numpy(region).astype(np.int64), minlength=2)
        say("     Region: %d kept (0), %d new (1) of %d cells" % (counts[0], counts[1], n_cells))
        check(len(counts) == 2 and counts[1] > 0 and counts[0] > 0,
              "Region: new cells (1) and kept cells (0), no other value")
        kept, new = field_value("KeptCells"), field_value("NewCells")
        check(str(counts[0]) == kept and str(counts[1]) == new,
              "Region's counts = the filter's KeptCells / NewCells (%s / %s)" % (kept, new))
    surfaces = field_value("NumberOfSurfaces")
    check(surfaces is not None and int(float(surfaces)) >= 1,
          "AdaptToShocks's output: NumberOfSurfaces = %s (%s)" % (surfaces, field_value("SurfaceTemplates")))
    nodes_in, nodes_out = field_value("InputNodes"), field_value("OutputNodes")
    check(nodes_in == str(INPUT_NODES) and nodes_out == str(n_points),
          "InputNodes = %s (cone20Ma2p5.vtu), OutputNodes = %s = the file's points" % (nodes_in, nodes_out))

check(os.path.exists(png), "screenshot saved")
if os.path.exists(png):
    img = read_png(png)
    check(img.shape[:2] == (HEIGHT, WIDTH),
          "screenshot is %d x %d (%d x %d)" % (WIDTH, HEIGHT, img.shape[1], img.shape[0]))
    colours = len(np.unique(img[..., 0] * 65536 + img[..., 1] * 256 + img[..., 2]))
    check(colours > 100, "picture has %d distinct colours" % colours)
    view = render_view(img)
    check(view is not None, "the render view (its background colour) is in the picture")
    if view is not None:
        x0, x1, y0, y1 = view
        sub = img[y0:y1, x0:x1]
        fraction = np.mean(np.abs(sub - BACKGROUND).sum(axis=2) > 30)
        red, blue = region_pixels(sub)
        check((x1 - x0) * (y1 - y0) > 0.25 * WIDTH * HEIGHT,
              "render view %d x %d at (%d, %d)" % (x1 - x0, y1 - y0, x0, y0))
        check(0.05 < fraction < 0.9, "non-background pixels: %.3f of the render view" % fraction)
        check(red > 5000, "new cells (Region = 1, red) cover %d pixels" % red)
        check(blue > 5000, "kept cells (Region = 0, blue) cover %d pixels" % blue)
if "seconds" in stats:
    say("     Adapt To Shocks in the GUI: %.1f s; the whole test %.1f s" % (stats["seconds"], time.monotonic() - START))
artest.finish()
