"""The page's arcs, paths and rectangular containers (SPEC §14, §15) in the real browser against
the real binary: called by test_page.py with its driver and server.

- An arc of a rotary table: the page's plan equals the API's plan of the same request written
  here; the top view's path ends where the arc of that radius and angle ends (closed form), the
  container's heading turns with the table; each peak arrow points in the wall direction of the
  plan's planar peaks (its `path` block, else the API's planar simulation of its law) and sits
  where the container is at the peak's time,
  computed here from the law's seven durations by exact integration of its piecewise-constant
  jerk; the η plot is the maximum over the wall (the API's planar figures), not the
  straight-line η; the view's link reproduces it in a fresh browser.
- A rectangular cup of a form-fill-seal line: the page's plan equals the API's plan of the same
  request; the form's drawing and the top view turn the cup by its orientation (corners computed
  here).
- A path opened by its key: the segment rows, start heading and turning refilled, the preview
  drawn, and Plan sends the request the plan was made with.
- Refusals: a path segment with a bad radius and a cup turned out of range get the API's message
  at the input of the field the API names, and nowhere else.
"""

import math
import os

from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

CUP = {"length": "120", "width": "80", "orientation": "30", "height": "70", "fill": "40",
       "stroke": "300", "time": "0.8"}


def set_value(driver, element_id, value):
    el = driver.find_element(By.ID, element_id)
    el.clear()
    el.send_keys(value)


def choose(driver, element_id, value):
    Select(driver.find_element(By.ID, element_id)).select_by_value(value)


def errors_shown(driver):
    return driver.execute_script(
        "return Object.fromEntries([...document.querySelectorAll('.field-error, .form-error')]"
        ".filter(e => e.textContent).map(e => [e.id, e.textContent]))")


def marked(driver):
    return driver.execute_script("return [...document.querySelectorAll('[aria-invalid]')].map(e => e.id)")


def position_at(law, stroke_mm, t):
    """s(t) [mm] of a seven-segment law: jerk A/d1, 0, -A/d3, 0, -B/d5, 0, B/d7 on the seven
    durations, B from zero final velocity, the scale from s(T) = stroke; exact per segment."""
    d = law["durations_s"]

    def integrate(jerks, until):
        a = v = s = 0.0
        elapsed = 0.0
        for j, dt in zip(jerks, d):
            h = min(dt, max(0.0, until - elapsed))
            s += v * h + a * h * h / 2 + j * h ** 3 / 6
            v += a * h + j * h * h / 2
            a += j * h
            elapsed += dt
        return s, v

    def jerks(A, B):
        return [A / d[0] if d[0] else 0, 0, -A / d[2] if d[2] else 0, 0,
                -B / d[4] if d[4] else 0, 0, B / d[6] if d[6] else 0]

    # Velocity is linear in (A, B): zero at the end fixes B / A.
    _, v_a = integrate(jerks(1.0, 0.0), sum(d))
    _, v_b = integrate(jerks(0.0, 1.0), sum(d))
    unit = jerks(1.0, -v_a / v_b)
    scale = stroke_mm / integrate(unit, sum(d))[0]
    return scale * integrate(unit, t)[0]


def arc_point(radius, s):
    """A left arc from the origin heading +x: the point s along it."""
    return radius * math.sin(s / radius), radius * (1 - math.cos(s / radius))


def arc_request(strategy):
    return {"format": {"container": {"radius_mm": 48.5, "height_mm": 150.0}, "fill_height_mm": 82.0,
                       "fluid": "water", "motion_time_s": 1.2,
                       "motion": {"type": "arc", "radius_mm": 300.0, "angle_deg": 90.0, "container_turns": True}},
            "strategy": strategy, "options": {}}


def planar_simulation(api_json, port, plan):
    m = plan["model"]
    damping = {"zeta": m["zeta"]} if m["damping"] == "explicit" else m["damping"]
    format = {k: v for k, v in plan["format"].items() if k != "stroke_mm"}  # the motion is the move
    body = {"format": format, "law": plan["law"], "rest_time_s": plan["rest_time_s"],
            "options": {"damping": damping, "alpha": m["alpha"], "modes": len(m["f_hz"]), "min_ramp_s": 0.001},
            # The page's sampling: 2000 steps over the motion and the rest window.
            "sample_period_s": (plan["format"]["motion_time_s"] + plan["rest_time_s"]) / 2000}
    return api_json(port, "POST", "/v1/simulate", body)


def check_arc(driver, port, ctx):
    check, api_json, expected_row, table_rows = ctx["check"], ctx["api_json"], ctx["expected_row"], ctx["table_rows"]
    driver.get(f"http://127.0.0.1:{port}/")
    ctx["wait_for"](driver, "return document.body.dataset.loaded === '1'")
    for field, value in {"radius": "48.5", "height": "150", "fill": "82", "time": "1.2"}.items():
        set_value(driver, field, value)
    choose(driver, "motion_type", "arc")
    set_value(driver, "arc_radius", "300")
    set_value(driver, "arc_angle", "90")
    check(driver.find_element(By.ID, "arc_turns").is_selected(), "an arc's container turns with the table by default")
    check(not driver.find_element(By.ID, "stroke").is_displayed(), "an arc has no stroke input")
    preview = driver.execute_script("const l = document.querySelector('#motion-preview #path-line');"
                                    "return l && [Number(l.dataset.endX), Number(l.dataset.endY)]")
    check(preview is not None and abs(preview[0] - 300) < 1e-9 and abs(preview[1] - 300) < 1e-9,
          f"the form's preview draws the arc to (300, 300): {preview}")
    choose(driver, "strategy", "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    ctx["wait_for"](driver, "return document.body.dataset.ready === 'multi_notch'"
                            " || document.getElementById('status-line').textContent.startsWith('The service refused')"
                            " || document.getElementById('form-error').textContent")
    problem = driver.find_element(By.ID, "form-error").text
    check(problem == "", f"the arc's plan is drawn: {problem}")
    status, plan = api_json(port, "POST", "/v1/plans", arc_request("multi_notch"))
    check(status == 200, f"the API plans the arc ({status}: {plan})")
    if status != 200:
        return
    check(driver.execute_script("return window.sloshPage.request") == arc_request("multi_notch"),
          f"the page's request is the arc's: {driver.execute_script('return window.sloshPage.request')}")
    rows = table_rows(driver)
    check(len(rows) == 1 and rows[0]["cells"] == expected_row(plan), f"the table equals the API's arc plan: {rows}")
    # The peaks over the wall and the η(t) series: the API's planar simulation of the plan's law.
    status, sim = planar_simulation(api_json, port, plan)
    check(status == 200 and "series" in sim, f"the API simulates the plan's law on the arc with its series ({status})")
    if status != 200 or "series" not in sim:
        return
    end = driver.execute_script("const l = document.querySelector('#top-view #path-line');"
                                "return [Number(l.dataset.endX), Number(l.dataset.endY), Number(l.dataset.lengthMm)]")
    check(abs(end[0] - 300) < 1e-9 and abs(end[1] - 300) < 1e-9 and abs(end[2] - 150 * math.pi) < 1e-9,
          f"the top view's path ends at (300, 300) after 150π mm: {end}")
    check(abs(sim["motion"]["length_mm"] - 150 * math.pi) < 1e-6, f"the service's arc length is 150π mm: {sim['motion']}")
    headings = driver.execute_script("return [...document.querySelectorAll('#top-view .ghost')]"
                                     ".map(g => Number(g.dataset.headingDeg))")
    check(len(headings) == 5 and all(abs(h - 22.5 * k) < 1e-9 for k, h in enumerate(headings)),
          f"the container turns with the table: headings {headings}")
    check(plan["law"]["type"] == "seven_segment", f"multi_notch plans a seven-segment law: {plan['law']['type']}")
    for model in ("nonlinear", "linear"):
        p = sim["prediction"][model]
        for when in ("motion", "rest"):
            arrow = driver.execute_script(
                f"const g = document.getElementById('peak-{when}-{model}');"
                "return g && Object.fromEntries(Object.entries(g.dataset).map(([k, v]) => [k, Number(v)]))")
            what = f"the {when} peak of the {model} model"
            check(arrow is not None, f"{what} is drawn")
            if arrow is None:
                continue
            check(arrow["directionDeg"] == p[f"direction_{when}_deg"] and arrow["etaMm"] == p[f"eta_{when}_mm"],
                  f"{what} points where the API says: {arrow} vs {p}")
            s = position_at(plan["law"], 150 * math.pi, p[f"t_{when}_s"]) if when == "motion" else 150 * math.pi
            x, y = arc_point(300.0, s)
            # The page interpolates s(t) between the samples of a 2000-sample series: well under 0.05 mm.
            check(abs(arrow["x"] - x) < 0.05 and abs(arrow["y"] - y) < 0.05,
                  f"{what} sits where the container is at t = {p[f't_{when}_s']}: ({arrow['x']}, {arrow['y']}) vs ({x}, {y})")
    charts = driver.execute_script(
        "return window.sloshPage.charts.map(c => ({id: c.canvas.id, data: c.data.datasets.map(d => d.data)}))")
    ids = [c["id"] for c in charts]
    check("plot-eta" not in ids and "plot-eta-wall" in ids, f"the η plot is the maximum over the wall: {ids}")
    wall = next((c["data"] for c in charts if c["id"] == "plot-eta-wall"), None)
    check(wall is not None, f"the η plot over the wall is drawn: {ids}")
    if wall is not None:
        # Every sample of the service's series, the maximum over the wall of each model, not two
        # peak points.
        series = sim["series"]
        for k, model in enumerate(("nonlinear", "linear")):
            expected = [{"x": t, "y": y} for t, y in zip(series["t_s"], series[f"eta_{model}_mm"])]
            check(len(wall[k]) == len(expected) > 1000 and wall[k] == expected,
                  f"the η plot holds the API's {model} series over the wall: {len(wall[k])} points "
                  f"vs {len(expected)}")
    if ctx.get("artifacts"):  # the screenshot of docs/web-page.md
        driver.execute_script("window.scrollTo(0, 0)")
        driver.save_screenshot(os.path.join(ctx["artifacts"], "arc.png"))
    check_arc_link(driver, ctx, plan)


ARROWS = ("return [...document.querySelectorAll('#top-view .peak')]"
          ".map(g => [g.id, g.dataset.x, g.dataset.y, g.dataset.directionDeg])")


def check_arc_link(driver, ctx, plan):
    """The link of the arc's view reproduces its table and top view in a fresh browser."""
    link = driver.find_element(By.ID, "share-link").get_attribute("href")
    ctx["check"]("motion=arc" in link and "arc_r=300" in link and "arc_turns=1" in link and "stroke=" not in link,
                 f"the link holds the arc, not a stroke: {link}")
    arrows = driver.execute_script(ARROWS)
    fresh = ctx["browser"]()
    try:
        fresh.get(link)
        ctx["wait_for"](fresh, "return document.body.dataset.ready === 'multi_notch'")
        ctx["check"](ctx["table_rows"](fresh)[0]["cells"] == ctx["expected_row"](plan), "the arc's link reproduces the table")
        ctx["check"](fresh.execute_script(ARROWS) == arrows and len(arrows) == 4,
                     f"the arc's link reproduces the peak arrows: {arrows}")
    finally:
        fresh.quit()


def cup_request(strategy):
    return {"format": {"container": {"shape": "rectangular", "length_mm": 120.0, "width_mm": 80.0,
                                     "orientation_deg": 30.0, "height_mm": 70.0},
                       "fill_height_mm": 40.0, "fluid": "water", "stroke_mm": 300.0, "motion_time_s": 0.8},
            "strategy": strategy, "options": {}}


def corners(length, width, angle_deg):
    a = math.radians(angle_deg)
    return [(u * math.cos(a) - v * math.sin(a), u * math.sin(a) + v * math.cos(a))
            for u, v in ((length / 2, width / 2), (-length / 2, width / 2), (-length / 2, -width / 2), (length / 2, -width / 2))]


def polygon_points(driver, selector):
    text = driver.execute_script(f"const p = document.querySelector({selector!r}); return p && p.getAttribute('points')")
    if not text:
        return None
    return [(float(x), -float(y)) for x, y in (pair.split(",") for pair in text.split())]


def check_cup(driver, port, ctx):
    check, api_json, expected_row, table_rows = ctx["check"], ctx["api_json"], ctx["expected_row"], ctx["table_rows"]
    driver.get(f"http://127.0.0.1:{port}/")
    ctx["wait_for"](driver, "return document.body.dataset.loaded === '1'")
    choose(driver, "shape", "rectangular")
    check(not driver.find_element(By.ID, "radius").is_displayed(), "a rectangular cup has no radius input")
    for field, value in CUP.items():
        set_value(driver, field, value)
    drawn = polygon_points(driver, "#tank-view polygon")
    expected = corners(120, 80, 30)
    check(drawn is not None and all(math.dist(p, q) < 1e-9 for p, q in zip(drawn, expected)),
          f"the form draws the cup turned 30° to the motion: {drawn} vs {expected}")
    choose(driver, "strategy", "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    ctx["wait_for"](driver, "return document.body.dataset.ready === 'multi_notch'"
                            " || document.getElementById('status-line').textContent.startsWith('The service refused')"
                            " || document.getElementById('form-error').textContent")
    problem = driver.find_element(By.ID, "form-error").text
    check(problem == "", f"the cup's plan is drawn: {problem}")
    status, plan = api_json(port, "POST", "/v1/plans", cup_request("multi_notch"))
    check(status == 200, f"the API plans the cup ({status}: {plan})")
    if status != 200:
        return
    rows = table_rows(driver)
    check(len(rows) == 1 and rows[0]["cells"] == expected_row(plan), f"the table equals the API's cup plan: {rows}")
    first = polygon_points(driver, "#top-view .ghost polygon")
    check(first is not None and all(math.dist(p, q) < 1e-9 for p, q in zip(first, expected)),
          f"the top view draws the cup at the start turned 30°: {first}")
    ids = [c["id"] for c in ctx["chart_counts"](driver)]
    check("plot-eta" in ids and "plot-acceleration" in ids, f"the cup's plan is plotted: {ids}")
    # The η plot is the wave of the plan's own model (the tank's damping, not a cylinder's): its
    # sampled peak during the motion is the plan's, to the sampling (2000 samples).
    eta = driver.execute_script(
        "const c = window.sloshPage.charts.find(c => c.canvas.id === 'plot-eta');"
        "return c && c.data.datasets[0].data.filter(p => p.x <= arguments[0]).map(p => Math.abs(p.y))", 0.8)
    peak = plan["prediction"]["nonlinear"]["eta_motion_mm"]
    check(eta and abs(max(eta) - peak) < 1e-3 * peak, f"the η plot peaks at the plan's η motion {peak} mm: {eta and max(eta)}")
    check(driver.execute_script("return window.sloshPage.plans.multi_notch.format.container") ==
          plan["format"]["container"], "the page keeps the API's echo of the cup")


def check_refusal(driver, port, ctx, setup, request_of, element_id, field):
    """The form as `setup` leaves it is planned; the API refuses the same request (written here)
    naming `field`; the page shows exactly that message at `element_id`, marked invalid."""
    check, api_json = ctx["check"], ctx["api_json"]
    driver.get(f"http://127.0.0.1:{port}/")
    ctx["wait_for"](driver, "return document.body.dataset.loaded === '1'")
    setup(driver)
    choose(driver, "strategy", "notch")
    driver.find_element(By.ID, "plan-button").click()
    ctx["wait_for"](driver, "return document.getElementById('status-line').textContent.startsWith('The service refused')"
                            " || document.body.dataset.ready")
    status, error = api_json(port, "POST", "/v1/plans", request_of)
    check(status == 422 and error["error"]["field"] == field, f"the API refuses {field}: {status} {error}")
    if status != 422:
        return
    message = error["error"]["message"]
    check(errors_shown(driver) == {f"{element_id}-error": message},
          f"the API's message at #{element_id} only: {errors_shown(driver)} vs {message!r}")
    check(marked(driver) == [element_id], f"#{element_id} alone is marked invalid: {marked(driver)}")


def check_refusals(driver, port, ctx):
    def bad_segment(driver):
        choose(driver, "motion_type", "path")
        set_value(driver, "seg1_radius", "-20")

    path = {"format": {"container": {"radius_mm": 48.5, "height_mm": 150.0}, "fill_height_mm": 82.0,
                       "fluid": "water", "motion_time_s": 1.0,
                       "motion": {"type": "path", "container_turns": False,
                                  "segments": [{"line_mm": 200.0}, {"arc": {"radius_mm": -20.0, "angle_deg": 90.0}},
                                               {"line_mm": 200.0}]}},
            "strategy": "notch", "options": {}}
    check_refusal(driver, port, ctx, bad_segment, path, "seg1_radius", "format.motion.segments[1].arc.radius_mm")

    def turned_too_far(driver):
        choose(driver, "shape", "rectangular")
        for field, value in CUP.items():
            set_value(driver, field, value)
        set_value(driver, "orientation", "200")

    cup = cup_request("notch")
    cup["format"]["container"]["orientation_deg"] = 200.0
    check_refusal(driver, port, ctx, turned_too_far, cup, "orientation", "format.container.orientation_deg")


def check_path_key(port, ctx):
    """A plan along a path opened by its key fills the form with its motion (the segment rows,
    the start heading, the container's turning) and its drawing, and Plan sends the same request."""
    check = ctx["check"]
    request = {"format": {"container": {"radius_mm": 48.5, "height_mm": 150.0}, "fill_height_mm": 82.0,
                          "fluid": "water", "motion_time_s": 1.5,
                          "motion": {"type": "path", "start_heading_deg": 30.0, "container_turns": True,
                                     "segments": [{"line_mm": 150.0}, {"arc": {"radius_mm": 120.0, "angle_deg": -60.0}},
                                                  {"line_mm": 80.0}, {"arc": {"radius_mm": 200.0, "angle_deg": 45.0}}]}},
               "strategy": "notch", "options": {}}
    status, plan = ctx["api_json"](port, "POST", "/v1/plans", request)
    check(status == 200, f"the API plans the path ({status}: {plan})")
    if status != 200:
        return
    driver = ctx["browser"]()
    try:
        driver.get(f"http://127.0.0.1:{port}/?key={plan['key']}")
        ctx["wait_for"](driver, "return document.body.dataset.ready === 'notch'")
        rows = driver.execute_script(
            "return [...document.querySelectorAll('#segments .segment')].map((r, i) => "
            "[document.getElementById(`seg${i}_kind`).value, ...[...r.querySelectorAll('[data-field]')]"
            ".filter(e => !e.closest('[hidden]')).map(e => e.value)])")
        check(rows == [["line", "150"], ["arc", "120", "-60"], ["line", "80"], ["arc", "200", "45"]],
              f"the key view fills the segment rows: {rows}")
        check(driver.find_element(By.ID, "path_turns").is_selected() and
              driver.find_element(By.ID, "path_heading").get_attribute("value") == "30",
              "the key view fills the start heading and the turning")
        end = driver.execute_script("const l = document.querySelector('#motion-preview #path-line');"
                                    "return l && Number(l.dataset.lengthMm)")
        length = 150 + 120 * math.pi / 3 + 80 + 200 * math.pi / 4
        check(end is not None and abs(end - length) < 1e-9, f"the preview draws the opened path: {end} vs {length}")
        driver.execute_script("delete document.body.dataset.ready")
        driver.find_element(By.ID, "plan-button").click()
        ctx["wait_for"](driver, "return document.body.dataset.ready"
                                " || document.getElementById('status-line').textContent.startsWith('The service refused')"
                                " || document.getElementById('form-error').textContent")
        check(errors_shown(driver) == {}, f"the opened path plans again: {errors_shown(driver)}")
        check(driver.execute_script("return window.sloshPage.request") == request,
              f"Plan sends the opened path's request: {driver.execute_script('return window.sloshPage.request')}")
    finally:
        driver.quit()


def run(driver, port, ctx):
    check_path_key(port, ctx)
    check_arc(driver, port, ctx)
    check_cup(driver, port, ctx)
    check_refusals(driver, port, ctx)
    driver.get(f"http://127.0.0.1:{port}/")  # the next checks start from a fresh form
    ctx["wait_for"](driver, "return document.body.dataset.loaded === '1'")
