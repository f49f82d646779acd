#!/usr/bin/python3
"""The review page (index.html) of `cvc render --display` in a real browser.

Renders a small fly-through of a colon phantom, opens file://.../index.html in headless Chromium
through Selenium and checks what a reader relies on: no console errors, the slider and the keys
step frames, the large sheet and every wall image shown are the current frame's and loaded, the
pose and the arc length are the manifest's, the three CT slices are drawn with the camera on
them; given the sections a coverage run adds, they show and a patch's row jumps to its frame;
a render posed at polyp candidates lists them, sorts them, and a row shows its frame with the
candidate ringed in each cross of the sheet. The same checks must find fault with broken copies of the page (a data file or an image
missing), so a page that does not work cannot pass.

  review_page_test.py --cvc build/app/cvc --work DIR        the test (CTest runs it)
  review_page_test.py --page DIR [--screenshot FILE.png]    check a rendered page (and screenshot it)

Needs Debian's chromium, chromium-driver and python3-selenium (scripts/setup.sh installs them);
run it with /usr/bin/python3, where python3-selenium lives.
"""
import argparse
import importlib.util
import json
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

LOAD_TIMEOUT_S = 30
IMAGE_TIMEOUT_S = 15

# Walls of a few dozen pixels: the render takes a second, the page is the one of any display.
TINY_DISPLAY = {
    "name": "tiny-ic", "box_size_m": [2.95, 2.21, 2.95], "map": "none",
    "walls": [{"name": n, "width": 64, "height": 48} for n in ("front", "back", "left", "right")]
    + [{"name": "floor", "width": 48, "height": 48}],
}
FRAMES = 4


def fail(message):
    print(f"review_page_test: FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def import_selenium():
    if importlib.util.find_spec("selenium") is None:
        fail(f"python3-selenium is missing for {sys.executable}: install Debian's python3-selenium, chromium and "
             "chromium-driver (scripts/setup.sh does) and run this test with /usr/bin/python3")


def start_browser(profile, width, height):
    from selenium import webdriver
    from selenium.webdriver.chrome.options import Options
    from selenium.webdriver.chrome.service import Service

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    driver = shutil.which("chromedriver") or "/usr/bin/chromedriver"
    for program, package in ((chromium, "chromium"), (driver, "chromium-driver")):
        if not Path(program).exists():
            fail(f"{program} not found: install Debian's {package} (scripts/setup.sh installs chromium, "
                 "chromium-driver and python3-selenium)")
    options = Options()
    options.binary_location = chromium
    # Root in CI cannot use Chromium's sandbox; no display, no GPU. A profile of our own so that
    # parallel runs do not share one. File access stays as a user's browser has it: the page must
    # work without --allow-file-access-from-files.
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
                     "--hide-scrollbars", "--force-device-scale-factor=1", f"--user-data-dir={profile}",
                     f"--window-size={width},{height}"):
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    browser = webdriver.Chrome(service=Service(executable_path=driver), options=options)
    browser.set_page_load_timeout(LOAD_TIMEOUT_S)
    browser.set_script_timeout(LOAD_TIMEOUT_S)
    return browser


def poll(condition, timeout_s):
    """condition() until it returns something true or the time is up; its last value."""
    deadline = time.monotonic() + timeout_s
    while True:
        value = condition()
        if value or time.monotonic() > deadline:
            return value
        time.sleep(0.05)


STATE_SCRIPT = """
const large = document.getElementById('large');
const images = [large, ...document.querySelectorAll('#image-groups img')];
return {
  slider: document.getElementById('slider').value,
  sliderMax: document.getElementById('slider').max,
  large: large.getAttribute('src'),
  walls: [...document.querySelectorAll('#image-groups img')].map(i => i.getAttribute('src')),
  pending: images.filter(i => !i.complete).length,
  unloaded: images.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('src')),
  label: document.getElementById('frame-label').textContent,
  pose: document.getElementById('pose').textContent,
  current: [...document.querySelectorAll('#strip figure')].findIndex(f => f.classList.contains('current')),
};
"""

# Per slice canvas: how its pixels vary, how many are the camera's yellow, and its shape.
SLICE_SCRIPT = """
return [...document.querySelectorAll('#slices canvas')].map(canvas => {
  const pixels = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
  let sum = 0, squares = 0, yellow = 0;
  const count = pixels.length / 4;
  for (let i = 0; i < pixels.length; i += 4) {
    const luma = 0.299 * pixels[i] + 0.587 * pixels[i + 1] + 0.114 * pixels[i + 2];
    sum += luma; squares += luma * luma;
    if (pixels[i] > 200 && pixels[i + 1] > 170 && pixels[i + 2] < 140) ++yellow;
  }
  const mean = sum / count;
  return {view: canvas.dataset.view, width: canvas.width, height: canvas.height,
          mean: mean, deviation: Math.sqrt(Math.max(0, squares / count - mean * mean)), yellow: yellow};
});
"""


AXIAL_SCRIPT = "const c = document.querySelector('#slices canvas'); return c ? c.toDataURL() : null;"


def set_slider(browser, position):
    browser.execute_script("const s = document.getElementById('slider'); s.value = String(arguments[0]);"
                           "s.dispatchEvent(new Event('input', {bubbles: true}));", position)


def press(browser, key):
    from selenium.webdriver.common.action_chains import ActionChains
    ActionChains(browser).send_keys(key).perform()


def arc_lengths(poses):
    arcs, total = [], 0.0
    for i, pose in enumerate(poses):
        if i:
            total += math.dist(pose["position_mm"], poses[i - 1]["position_mm"])
        arcs.append(total)
    return arcs


def expected_frame(folder, manifest, position):
    """What frame `position` must show: its sheet, its walls for both eyes, its pose and arc length."""
    name = f"frame_{position:04d}"
    walls = [w["name"] for w in manifest["display"]["walls"]]
    images = [f"{name}/{eye}/{wall}.png" for eye in ("left", "right") for wall in walls]
    if (folder / name / "before_after.png").exists():
        images.append(f"{name}/before_after.png")
    pose = manifest["poses"][position]
    return {"sheet": f"{name}/sheet.png", "walls": images, "arc": arc_lengths(manifest["poses"])[position],
            "position": "(" + ", ".join(f"{x:.1f}" for x in pose["position_mm"]) + ") mm"}


def check_frame(browser, folder, manifest, position, how):
    """Problems with the page's view of frame `position` after `how` moved to it."""
    problems = []
    want = expected_frame(folder, manifest, position)
    count = len(manifest["poses"])
    # Until every image has loaded or failed (a missing file fails at once from the file system).
    state = poll(lambda: (lambda s: s if not s["pending"] else None)(browser.execute_script(STATE_SCRIPT)),
                 IMAGE_TIMEOUT_S) or browser.execute_script(STATE_SCRIPT)
    if state["slider"] != str(position):
        problems.append(f"{how}: the slider shows {state['slider']}, not frame {position}")
    if state["sliderMax"] != str(count - 1):
        problems.append(f"the slider runs to {state['sliderMax']}, not {count - 1}")
    if state["large"] != want["sheet"]:
        problems.append(f"{how}: the large image is {state['large']}, not {want['sheet']}")
    if state["walls"] != want["walls"]:
        problems.append(f"{how}: the frame's images are {state['walls']}, not {want['walls']}")
    if state["unloaded"]:
        problems.append(f"{how}: images did not load: {state['unloaded']}")
    if state["current"] != position:
        problems.append(f"{how}: the film strip marks frame {state['current']}, not {position}")
    label = f"frame {position + 1} of {count} \u00b7 {want['arc']:.1f} mm along the path"
    if state["label"] != label:
        problems.append(f"{how}: the frame label reads {state['label']!r}, not {label!r}")
    if want["position"] not in state["pose"]:
        problems.append(f"{how}: the pose {state['pose']!r} lacks the position {want['position']}")
    return problems


def check_slices(browser, folder):
    problems = []
    slices = browser.execute_script(SLICE_SCRIPT)
    if [s["view"] for s in slices] != ["axial", "coronal", "sagittal"]:
        return [f"slice canvases: {[s['view'] for s in slices]}, not axial, coronal, sagittal"]
    volume_text = (folder / "review_volume.js").read_text()
    volume = json.loads(volume_text[volume_text.index("=") + 1:].rstrip().rstrip(";"))
    for s, view in zip(slices, volume["views"]):
        if s["deviation"] < 8:
            problems.append(f"the {s['view']} slice is blank (grey deviation {s['deviation']:.1f})")
        if s["yellow"] < 10:
            problems.append(f"the {s['view']} slice lacks the camera ({s['yellow']} yellow pixels)")
        width_mm = volume["dims"][view["column_axis"]] * volume["spacing_mm"][view["column_axis"]]
        height_mm = volume["dims"][view["row_axis"]] * volume["spacing_mm"][view["row_axis"]]
        if abs(s["width"] / s["height"] - width_mm / height_mm) > 0.02 * width_mm / height_mm + 2 / s["height"]:
            problems.append(f"the {s['view']} slice is {s['width']}x{s['height']} px for {width_mm:.0f}x{height_mm:.0f} mm")
    return problems


def severe_messages(browser):
    return [entry["message"] for entry in browser.get_log("browser") if entry["level"] == "SEVERE"]


def check_page(browser, folder):
    """Everything wrong with the page in `folder`, as sentences; none for a working page."""
    from selenium.webdriver.common.keys import Keys

    severe_messages(browser)  # what an earlier page logged is not this page's
    manifest = json.loads((folder / "render.json").read_text())
    count = len(manifest["poses"])
    # get() returns after the load event, so the page's scripts have run by then.
    browser.get((folder / "index.html").resolve().as_uri())
    ready = poll(lambda: browser.execute_script("return document.body.getAttribute('data-ready')") == "1", 2)
    problems = [] if ready else ["the page never finished its start (data-ready)"]
    if ready:
        problems += check_frame(browser, folder, manifest, 0, "on opening")
        problems += check_slices(browser, folder)
    if ready and count >= 3:
        set_slider(browser, 2)
        problems += check_frame(browser, folder, manifest, 2, "slider set to 2")
        axial_at_2 = browser.execute_script(AXIAL_SCRIPT)
        press(browser, Keys.ARROW_LEFT)
        problems += check_frame(browser, folder, manifest, 1, "left arrow from 2")
        if axial_at_2 is not None and browser.execute_script(AXIAL_SCRIPT) == axial_at_2:
            problems.append("the axial slice did not change between frames 2 and 1")
        press(browser, Keys.END)
        problems += check_frame(browser, folder, manifest, count - 1, "End")
        press(browser, Keys.ARROW_RIGHT)
        problems += check_frame(browser, folder, manifest, count - 1, "right arrow at the last frame")
        press(browser, Keys.HOME)
        problems += check_frame(browser, folder, manifest, 0, "Home")
    problems += [f"console error: {message}" for message in severe_messages(browser)]
    problems_box = browser.execute_script("const p = document.getElementById('problems'); return p && !p.hidden ? p.textContent : ''")
    if problems_box:
        problems.append(f"the page reports: {problems_box}")
    return problems


def full_page_screenshot(browser, path, width):
    height = browser.execute_script("return document.documentElement.scrollHeight")
    browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False})
    # Now that the whole page is in view, the lazy thumbnails load too.
    poll(lambda: browser.execute_script("return [...document.images].every(i => i.complete)"), IMAGE_TIMEOUT_S)
    time.sleep(0.3)
    browser.save_screenshot(str(path))
    browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})


def run(command, what):
    result = subprocess.run(command, capture_output=True, text=True, timeout=300)
    if result.returncode != 0:
        fail(f"{what} failed ({' '.join(map(str, command))}):\n{result.stderr}")
    return result


def render_fly_through(cvc, work):
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    run([cvc, "phantom", "--size", "64", "--spacing", "2.4", "--force", "-o", work / "colon.nrrd"], "cvc phantom")
    (work / "tiny.json").write_text(json.dumps(TINY_DISPLAY))
    out = work / "flythrough"
    run([cvc, "render", work / "colon.nrrd", "--display", work / "tiny.json", "--path", work / "colon.json",
         "--frames", str(FRAMES), "--path-step", "20", "--scale", "4", "-o", out], "cvc render --display")
    for name in ("index.html", "review_data.js", "review_volume.js", "review_page.js", "review_page.css"):
        if not (out / name).is_file():
            fail(f"cvc render --display wrote no {name} in {out}")
    return out


def broken_copies(out, work):
    """Copies of the page with one part missing, each with what is missing."""
    copies = []
    for label, remove in (("review_data.js missing", "review_data.js"),
                          ("review_volume.js missing", "review_volume.js"),
                          ("review_page.js missing", "review_page.js"),
                          ("frame 1's left front wall missing", "frame_0001/left/front.png")):
        copy = work / ("broken_" + remove.replace("/", "_"))
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(out, copy)
        (copy / remove).unlink()
        copies.append((label, copy))
    return copies


def with_coverage(out, work):
    """A copy of the page given the sections a coverage run fills, as writeReviewPage writes them."""
    copy = work / "with_coverage"
    shutil.rmtree(copy, ignore_errors=True)
    shutil.copytree(out, copy)
    text = (copy / "review_data.js").read_text()
    data = json.loads(text[text.index("=") + 1:].rstrip().rstrip(";"))
    pose = {"position_mm": [1, 2, 3], "forward": [0, 0, 1], "up": [0, 1, 0]}
    data["coverage"] = {
        "percent": 82.4, "seen_mm2": 12345.6, "wall_mm2": 14982.0, "overview": "frame_0000/sheet.png",
        "description": "a test", "cumulative_percent": [20.0, 45.0, 70.0, 82.4][:len(data["frames"])],
        "patches": [{"rank": 1, "area_mm2": 120.5, "centre_mm": [1, 2, 3], "pose": pose, "nearest_frame": 2,
                     "picture": "frame_0002/left/front.png"},
                    {"rank": 2, "area_mm2": 40.2, "centre_mm": [7, 8, 9], "pose": pose, "nearest_frame": -1,
                     "picture": ""}]}
    data["measurements"] = [{"label": "polyp 3 diameter", "value": "9.8 mm"}]
    (copy / "review_data.js").write_text("window.REVIEW = " + json.dumps(data) + ";\n")
    return copy


COVERAGE_SCRIPT = """
return {
  shown: !document.getElementById('coverage').hidden,
  figure: (document.querySelector('.coverage-figure') || {}).textContent,
  curve: document.querySelectorAll('#coverage-curve polyline').length,
  patches: document.querySelectorAll('#patches tr.patch').length,
  measurements: document.getElementById('measurement-table').textContent,
  measurementsShown: !document.getElementById('measurements').hidden,
};
"""


def check_coverage(browser, folder):
    """Problems with the coverage and measurement sections; a patch's row must jump to its frame."""
    manifest = json.loads((folder / "render.json").read_text())
    problems = check_page(browser, folder)
    state = browser.execute_script(COVERAGE_SCRIPT)
    if not state["shown"] or state["figure"] != "82.4 %" or state["curve"] != 1 or state["patches"] != 2:
        problems.append(f"the coverage section is wrong: {state}")
    if not state["measurementsShown"] or "9.8 mm" not in state["measurements"]:
        problems.append(f"the measurements are not shown: {state}")
    browser.execute_script("document.querySelector('#patches tr.patch').click()")
    problems += check_frame(browser, folder, manifest, 2, "a click on patch 1")
    problems += [f"console error: {message}" for message in severe_messages(browser)]
    return problems


def coverage_run(cvc, work):
    """A short `cvc coverage` run of the test's phantom: the page the coverage command writes."""
    out = work / "coverage"
    run([cvc, "coverage", work / "colon.nrrd", "--path", work / "colon.json", "--display", work / "tiny.json",
         "--frames", str(FRAMES), "--path-step", "20", "--scale", "4", "--patch-pictures", "2", "--force",
         "-o", out], "cvc coverage")
    return out


def check_coverage_page(browser, folder):
    """Problems with a coverage run's page: its figure, its patches, a patch's row jumping to the
    patch's nearest frame with that frame's sheet loaded."""
    severe_messages(browser)
    result = json.loads((folder / "coverage.json").read_text())
    browser.get((folder / "index.html").resolve().as_uri())
    if not poll(lambda: browser.execute_script("return document.body.getAttribute('data-ready')") == "1", 2):
        return ["the coverage page never finished its start (data-ready)"]
    problems = []
    state = browser.execute_script(COVERAGE_SCRIPT)
    figure = f"{result['coverage_percent']:.1f} %"
    located = [p for p in result["patches"] if "pose" in p]
    if not state["shown"] or state["figure"] != figure or state["curve"] != 1 or state["patches"] != len(located):
        problems.append(f"the coverage section is wrong: {state}, expected {figure} and {len(located)} patches")
    if located:
        browser.execute_script("document.querySelector('#patches tr.patch').click()")
        frame = located[0]["nearest_frame"]
        want = f"frame_{frame:04d}/sheet.png"
        state = poll(lambda: (lambda s: s if not s["pending"] else None)(browser.execute_script(STATE_SCRIPT)),
                     IMAGE_TIMEOUT_S) or browser.execute_script(STATE_SCRIPT)
        if state["slider"] != str(frame) or state["large"] != want or state["unloaded"]:
            problems.append(f"a click on patch 1 shows {state['slider']} / {state['large']} (unloaded "
                            f"{state['unloaded']}), not frame {frame} / {want}")
    problems += [f"console error: {message}" for message in severe_messages(browser)]
    return problems


def candidates_run(cvc, work):
    """`cvc render --candidates --at-candidates` with a candidate list made here at the phantom's own polyps (the
    page is under test, not the detection): one frame per candidate, listed and ringed."""
    truth = json.loads((work / "colon.json").read_text())["polyps"]
    sessile = [p for p in truth if p["kind"] == "sessile"]
    candidates = [{"rank": i + 1, "centre_mm": p["centre_mm"], "diameter_mm": 2.0 * p["diameter_mm"],
                   "score": 0.9 - 0.1 * i, "shape_index": 0.95, "picture": None} for i, p in enumerate(sessile)]
    (work / "candidates.json").write_text(json.dumps({"candidates": candidates}))
    out = work / "candidates"
    run([cvc, "render", work / "colon.nrrd", "--display", work / "tiny.json", "--path", work / "colon.json",
         "--candidates", work / "candidates.json", "--at-candidates", "--polyp-elevation", "30", "--scale", "4", "--force", "-o", out],
        "cvc render --candidates")
    return out, candidates


def candidates_on_fly_through(cvc, work):
    """The fly-through again with the list of candidates_run placed on its frames (as cvc candidates
    places them at the same step): the page lists them, each row on its nearest frame."""
    listed = json.loads((work / "candidates.json").read_text())
    nearest = [2, 0, 3, 1]
    for candidate, frame in zip(listed["candidates"], nearest):
        candidate["nearest_frame"] = frame
    listed["path"] = {"step_mm": 20.0}
    (work / "candidates_on_path.json").write_text(json.dumps(listed))
    out = work / "flythrough_candidates"
    run([cvc, "render", work / "colon.nrrd", "--display", work / "tiny.json", "--path", work / "colon.json",
         "--frames", str(FRAMES), "--path-step", "20", "--scale", "4", "--candidates", work / "candidates_on_path.json",
         "--force", "-o", out], "cvc render --candidates (a fly-through)")
    return out, [c["nearest_frame"] for c in listed["candidates"]]


def check_fly_through_candidates(browser, folder, frames):
    """Problems with the candidates of a fly-through: each row on its nearest frame, a click shows it."""
    manifest = json.loads((folder / "render.json").read_text())
    problems = check_page(browser, folder)
    rows = browser.execute_script(
        "return [...document.querySelectorAll('#candidate-table tr.candidate')].map(tr => Number(tr.dataset.frame));")
    if rows != frames:
        problems.append(f"the rows' frames are {rows}, not the nearest frames {frames}")
    browser.execute_script("document.querySelector('#candidate-table tr.candidate').click()")
    problems += check_frame(browser, folder, manifest, frames[0], "a click on candidate 1")
    problems += [f"console error: {message}" for message in severe_messages(browser)]
    return problems


CANDIDATES_SCRIPT = """
const large = document.getElementById('large').getBoundingClientRect();
return {
  shown: !document.getElementById('candidates').hidden,
  ranks: [...document.querySelectorAll('#candidate-table tr.candidate')].map(tr => Number(tr.dataset.rank)),
  current: [...document.querySelectorAll('#candidate-table tr.current')].map(tr => Number(tr.dataset.rank)),
  rings: [...document.querySelectorAll('#rings .ring')].map(r => {
    const b = r.getBoundingClientRect();
    return {x: b.left + b.width / 2 - large.left, y: b.top + b.height / 2 - large.top, w: large.width, h: large.height};
  }),
};
"""


def check_candidates_page(browser, folder, candidates):
    """Problems with the candidates section: every candidate listed best first, a click on a row
    shows its frame and marks the row, a click on a title sorts, rings lie on the sheet."""
    manifest = json.loads((folder / "render.json").read_text())
    problems = check_page(browser, folder)
    state = browser.execute_script(CANDIDATES_SCRIPT)
    ranks = [c["rank"] for c in candidates]
    if not state["shown"] or state["ranks"] != ranks:
        problems.append(f"the candidates section lists {state['ranks']} (shown {state['shown']}), not {ranks}")
    if len(candidates) > 1:
        browser.execute_script("document.querySelectorAll('#candidate-table tr.candidate')[1].click()")
        problems += check_frame(browser, folder, manifest, 1, "a click on candidate 2")
        state = poll(lambda: (lambda s: s if s["rings"] else None)(browser.execute_script(CANDIDATES_SCRIPT)),
                     IMAGE_TIMEOUT_S) or browser.execute_script(CANDIDATES_SCRIPT)
        if state["current"] != [2]:
            problems.append(f"after the click the marked rows are {state['current']}, not [2]")
        # Left eye, right eye and anaglyph: a ring in each third of the sheet, inside the picture.
        thirds = sorted({int(3 * r["x"] / r["w"]) for r in state["rings"] if 0 <= r["x"] <= r["w"] and 0 <= r["y"] <= r["h"]})
        if thirds != [0, 1, 2]:
            problems.append(f"the rings of candidate 2 are not one in each cross of the sheet: {state['rings']}")
    # Sorting by score ascending reverses the list (scores fall with rank here).
    browser.execute_script("document.querySelector('#candidate-table th[data-key=score]').click()")
    browser.execute_script("document.querySelector('#candidate-table th[data-key=score]').click()")
    state = browser.execute_script(CANDIDATES_SCRIPT)
    if state["ranks"] != ranks[::-1]:
        problems.append(f"sorted by score, lowest first, the rows are {state['ranks']}, not {ranks[::-1]}")
    problems += [f"console error: {message}" for message in severe_messages(browser)]
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cvc", help="the cvc binary (test mode)")
    parser.add_argument("--work", help="scratch folder (test mode)")
    parser.add_argument("--page", help="a rendered folder to check and screenshot")
    parser.add_argument("--screenshot", help="where to write the screenshot (PNG)")
    parser.add_argument("--frame", type=int, default=0, help="the frame shown in the screenshot")
    parser.add_argument("--width", type=int, default=1500, help="browser width in CSS pixels")
    args = parser.parse_args()
    if not args.page and not (args.cvc and args.work):
        parser.error("give --cvc and --work (the test), or --page (a screenshot)")
    import_selenium()
    started = time.monotonic()

    # Checking a page writes nothing beside it: the browser's profile goes to a temporary folder.
    scratch = tempfile.TemporaryDirectory(prefix="review_page_") if args.page else None
    work = Path(scratch.name if scratch else args.work).resolve()
    work.mkdir(parents=True, exist_ok=True)
    out = Path(args.page).resolve() if args.page else render_fly_through(Path(args.cvc).resolve(), work)
    rendered = time.monotonic()

    browser = start_browser(work / "chromium_profile", args.width, 1100)
    try:
        is_coverage_page = args.page and not (out / "render.json").exists()
        problems = check_coverage_page(browser, out) if is_coverage_page else check_page(browser, out)
        if problems:
            fail(f"the page in {out} does not work:\n  " + "\n  ".join(problems))
        print("review_page_test: the page works")
        screenshot = Path(args.screenshot) if args.screenshot else None if args.page else work / "review_page.png"
        if screenshot:
            if args.frame:
                set_slider(browser, args.frame)
            full_page_screenshot(browser, screenshot, args.width)
            print(f"review_page_test: screenshot {screenshot}")
        if not args.page:
            problems = check_coverage(browser, with_coverage(out, work))
            if problems:
                fail("the page with coverage and measurements does not work:\n  " + "\n  ".join(problems))
            print("review_page_test: the coverage and measurement sections work")
            problems = check_coverage_page(browser, coverage_run(Path(args.cvc).resolve(), work))
            if problems:
                fail("the page of cvc coverage does not work:\n  " + "\n  ".join(problems))
            print("review_page_test: the page of cvc coverage works")
            candidates_out, candidates = candidates_run(Path(args.cvc).resolve(), work)
            problems = check_candidates_page(browser, candidates_out, candidates)
            if problems:
                fail("the candidates section does not work:\n  " + "\n  ".join(problems))
            print(f"review_page_test: the candidates section works ({len(candidates)} candidates)")
            problems = check_fly_through_candidates(browser, *candidates_on_fly_through(Path(args.cvc).resolve(), work))
            if problems:
                fail("the candidates of a fly-through do not work:\n  " + "\n  ".join(problems))
            print("review_page_test: the candidates of a fly-through work")
            copies = broken_copies(out, work)
            for label, copy in copies:
                caught = check_page(browser, copy)
                if not caught:
                    fail(f"a broken page passed the checks ({label}, {copy})")
                print(f"review_page_test: {label}: caught ({caught[0]})")
            print(f"review_page_test: each of {len(copies)} broken copies was caught")
    finally:
        browser.quit()
        if scratch:
            scratch.cleanup()
    print(f"review_page_test: render {rendered - started:.1f} s, browser {time.monotonic() - rendered:.1f} s")


if __name__ == "__main__":
    main()
