#!/usr/bin/python3
"""The web page of `slosh serve` in a real headless Chromium (SPEC §12).

Starts the real binary on a free loopback port (and, for the sub-path check, a small reverse
proxy in front of it), drives the page with Selenium and checks it against the API's own JSON:
the candidate table equals the plans' figures, every chart holds the API's point counts, an
invalid radius shows the API's message at the radius field, a shared URL reproduces the view,
the cam-table download equals `slosh export`'s file, and every input has a label. The robustness
chart holds the API's sweep (its points, limit and holding interval), uncertainty inputs go into
the URL and the request, and a refused range is shown at its input. "How fast can
it go?" (POST /v1/min-time): the table and headline equal the API's answer, the η-over-T charts
hold the API's curves, a row loads its plan at T_min, a shared link reproduces a search, and the
API's errors land at the fields they name. Every data-field path of the form is a member of the
service's published request schemas, every input's refused value shows the API's error next to
it, a late answer of an earlier request never replaces a later view, and an aborted request shows
no error. Arcs, paths and rectangular cups (the top view, the peak directions, their refusals):
motion_checks.py.

usage: test_page.py --slosh build/slosh --artifacts build/browser
"""

import argparse
import http.client
import http.server
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

from selenium import webdriver

import motion_checks
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

THESIS = {"radius": "48.5", "height": "150", "fill": "82", "stroke": "800", "time": "1"}
FAILURES = []


def check(condition, what):
    if not condition:
        FAILURES.append(what)
        print("FAIL:", what, flush=True)


def start_server(slosh, workdir):
    port_file = os.path.join(workdir, "port")
    log = open(os.path.join(workdir, "serve.log"), "w")
    proc = subprocess.Popen(
        [slosh, "serve", "--host", "127.0.0.1", "--port", "0", "--port-file", port_file,
         "--cache", os.path.join(workdir, "plans.sqlite"), "--workers", "2"],
        # The min-time view searches time_domain too (about 1 s, many times that under
        # AddressSanitizer): a budget it finishes in, so its answer is final and cached.
        env=dict(os.environ, SLOSH_SOLVE_BUDGET_S="120"),
        stdout=log, stderr=subprocess.STDOUT)
    for _ in range(200):
        if os.path.exists(port_file):
            text = open(port_file).read().strip()
            if text:
                return proc, int(text)
        if proc.poll() is not None:
            raise RuntimeError("slosh serve exited: " + open(log.name).read())
        time.sleep(0.05)
    raise RuntimeError("slosh serve did not report its port")


def api(port, method, path, body=None):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    data = None if body is None else json.dumps(body)
    conn.request(method, path, data, {"Content-Type": "application/json"})
    res = conn.getresponse()
    raw = res.read()
    return res.status, raw


def api_json(port, method, path, body=None):
    status, raw = api(port, method, path, body)
    return status, json.loads(raw)


class SubPathProxy(http.server.ThreadingHTTPServer):
    """Forwards /slosh/<rest> to the service's /<rest> (a reverse proxy at a sub-path)."""

    def __init__(self, backend_port):
        self.backend_port = backend_port
        super().__init__(("127.0.0.1", 0), ProxyHandler)


class ProxyHandler(http.server.BaseHTTPRequestHandler):
    def log_message(self, *args):
        pass

    def forward(self):
        if not self.path.startswith("/slosh/"):
            self.send_error(404, "outside the sub-path")
            return
        length = int(self.headers.get("Content-Length") or 0)
        body = self.rfile.read(length) if length else None
        conn = http.client.HTTPConnection("127.0.0.1", self.server.backend_port, timeout=60)
        headers = {k: v for k, v in self.headers.items() if k.lower() in ("content-type", "if-none-match")}
        conn.request(self.command, self.path[len("/slosh"):], body, headers)
        res = conn.getresponse()
        data = res.read()
        self.send_response(res.status)
        for k, v in res.getheaders():
            if k.lower() not in ("content-length", "connection", "keep-alive", "transfer-encoding"):
                self.send_header(k, v)
        self.send_header("Content-Length", str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    do_GET = forward
    do_POST = forward


def browser(downloads=None):
    options = webdriver.ChromeOptions()
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1280,800"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    if downloads:
        options.add_experimental_option("prefs", {"download.default_directory": downloads,
                                                  "download.prompt_for_download": False})
    return webdriver.Chrome(service=Service(shutil.which("chromedriver") or "/usr/bin/chromedriver"),
                            options=options)


def wait_for(driver, script, timeout=60.0):
    end = time.time() + timeout
    while time.time() < end:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(0.05)
    raise RuntimeError("timed out waiting for: " + script)


def fill_format(driver, values, strategy):
    for field, value in values.items():
        el = driver.find_element(By.ID, field)
        el.clear()
        el.send_keys(value)
    Select(driver.find_element(By.ID, "fluid")).select_by_value("water")
    Select(driver.find_element(By.ID, "strategy")).select_by_value(strategy)


def request_of(values, strategy):
    return {"format": {"container": {"radius_mm": float(values["radius"]), "height_mm": float(values["height"])},
                       "fill_height_mm": float(values["fill"]), "fluid": "water",
                       "stroke_mm": float(values["stroke"]), "motion_time_s": float(values["time"])},
            "strategy": strategy, "options": {}}


def fmt(value, digits=2):
    return "—" if value is None else f"{value:.{digits}f}"


def expected_row(plan):
    p, r, k = plan["prediction"], plan["reduction_pct"], plan["kinematics"]
    # Reductions on the linear model (the two laws' nonlinear figures of different models) say so.
    lin = " (lin)" if r.get("model") == "linear" else ""
    return [plan["strategy"], plan["status"], plan["law"]["type"],
            fmt(p["nonlinear"]["eta_motion_mm"]), fmt(p["nonlinear"]["eta_rest_mm"]),
            fmt(p["linear"]["eta_motion_mm"]), fmt(p["linear"]["eta_rest_mm"]),
            fmt(r["motion"], 1) + lin, fmt(r["rest"], 1) + lin, fmt(k["a_max"], 3), fmt(k["a_min"], 3),
            fmt(k["j_peak"], 1), "; ".join(plan.get("warnings", []))]


def table_rows(driver):
    return driver.execute_script(
        "return [...document.querySelectorAll('#candidates tbody tr')].map(tr => "
        "({strategy: tr.dataset.strategy, chosen: tr.classList.contains('chosen'), "
        "cells: [...tr.children].map(td => td.textContent)}))")


def chart_counts(driver):
    return driver.execute_script(
        "return window.sloshPage.charts.map(c => ({id: c.canvas.id, "
        "counts: c.data.datasets.map(d => d.data.length)}))")


def check_single_plan(driver, port):
    fill_format(driver, THESIS, "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch'")
    status, plan = api_json(port, "POST", "/v1/plans", request_of(THESIS, "multi_notch"))
    check(status == 200, f"the API plans the thesis format ({status})")
    rows = table_rows(driver)
    check(len(rows) == 1 and rows[0]["cells"] == expected_row(plan),
          f"the table equals the API's plan: {rows} vs {expected_row(plan)}")
    series_len = len(json.loads(api(port, "POST", "/v1/simulate", {
        "format": plan["format"], "law": plan["law"], "rest_time_s": plan["rest_time_s"],
        "options": {"damping": plan["model"]["damping"], "alpha": plan["model"]["alpha"],
                    "modes": len(plan["model"]["f_hz"]), "min_ramp_s": 0.001},
        "sample_period_s": (plan["format"]["motion_time_s"] + plan["rest_time_s"]) / 2000})[1])["series"]["t_s"])
    counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
    check(counts.get("plot-acceleration") == [series_len] * 3, f"acceleration chart points {counts}")
    check(counts.get("plot-velocity") == [series_len] * 3, f"velocity chart points {counts}")
    check(counts.get("plot-eta") == [series_len] * 4, f"eta chart points {counts}")
    spectrum = len(plan["spectrum"]["f_hz"])
    check(counts.get("plot-spectrum") == [spectrum, spectrum], f"spectrum chart points {counts}")
    check_robustness_chart(driver, plan, "thesis multi_notch")
    return plan


def robustness_markers(driver):
    return driver.execute_script(
        "const c = window.sloshPage.charts.find(c => c.canvas.id === 'plot-robustness');"
        "if (!c) return null; const m = c.options.plugins.markers;"
        "return {shade: m.shade.map(s => [s.from, s.to]), hlines: m.hlines.map(h => h.y),"
        " x: c.data.datasets.map(d => d.data.map(p => p.x))}")


def check_robustness_chart(driver, plan, what):
    """The robustness chart holds the API's sweep: one point per robustness.points entry on each
    of its four curves, at the API's deltas, the eta_rest limit as a line and the nonlinear
    holding interval shaded."""
    r = plan["robustness"]
    n = len(r["points"])
    counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
    check(counts.get("plot-robustness") == [n] * 4, f"{what}: robustness chart points {counts} vs {n}")
    markers = robustness_markers(driver) or {}
    deltas = [p["delta_pct"] for p in r["points"]]
    check(markers.get("x") == [deltas] * 4, f"{what}: the robustness chart is drawn over the API's deltas")
    check(markers.get("hlines") == [r["sweep"]["eta_rest_max_mm"]], f"{what}: the eta_rest limit line {markers}")
    holds = r["holds"]["nonlinear"]
    expected = [] if holds is None else [[holds["from_pct"], holds["to_pct"]]]
    check(markers.get("shade") == expected, f"{what}: the holding interval is shaded: {markers} vs {expected}")


UNCERTAINTY = {"omega_error": "5", "fill_min": "75", "fill_max": "90"}


def check_uncertainty(driver, port):
    """Uncertainty inputs go into the URL and the request, the page plots the API's sweep of
    them, a plan opened by its key fills them, and the API's refusal of a range lands at its
    input."""
    fill_format(driver, THESIS, "multi_notch")
    open_advanced = "document.querySelector('details').open = true"
    driver.execute_script(open_advanced)
    for field, value in UNCERTAINTY.items():
        driver.find_element(By.ID, field).send_keys(value)
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch'")
    url = driver.current_url
    check("omega_err=5" in url and "fill_lo=75" in url and "fill_hi=90" in url,
          f"the URL holds the uncertainty: {url}")
    sent = driver.execute_script("return window.sloshPage.request.options")
    check(sent == {"uncertainty": {"omega_error_pct": 5, "fill_height_mm": [75, 90]}},
          f"the request carries the uncertainty: {sent}")
    body = request_of(THESIS, "multi_notch")
    body["options"] = {"uncertainty": {"omega_error_pct": 5, "fill_height_mm": [75, 90]}}
    status, plan = api_json(port, "POST", "/v1/plans", body)
    check(status == 200 and "uncertainty" in plan, f"the API plans the range ({status})")
    shown = driver.execute_script("return window.sloshPage.plans.multi_notch.key")
    check(shown == plan["key"], f"the page shows the API's plan of the range: {shown} vs {plan['key']}")
    check(len(plan["robustness"]["points"]) == 22, "the sweep covers the range (21 points and delta = 0)")
    check_robustness_chart(driver, plan, "uncertainty")
    # The plan opened by its key fills the uncertainty inputs from the plan's echo.
    driver.get(f"http://127.0.0.1:{port}/?key={plan['key']}")
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch'")
    filled = {field: driver.find_element(By.ID, field).get_attribute("value") for field in UNCERTAINTY}
    check(filled == UNCERTAINTY, f"the key view fills the uncertainty inputs: {filled}")
    driver.execute_script(open_advanced)
    # An empty range: the API's message at the input of its minimum.
    for field, value in (("fill_min", "90"), ("fill_max", "70")):
        driver.find_element(By.ID, field).clear()
        driver.find_element(By.ID, field).send_keys(value)
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.getElementById('fill_min-error').textContent.length > 0", 20)
    body["options"]["uncertainty"]["fill_height_mm"] = [90, 70]
    status, error = api_json(port, "POST", "/v1/plans", body)
    check(status == 422 and error["error"]["field"] == "options.uncertainty.fill_height_mm",
          f"the API refuses the empty range: {error}")
    check(driver.find_element(By.ID, "fill_min-error").text == error["error"]["message"],
          "the fill height minimum shows the API's message")
    for field in UNCERTAINTY:
        driver.find_element(By.ID, field).clear()


def check_compare_all(driver, port, screenshot):
    driver.find_element(By.ID, "compare-button").click()
    wait_for(driver, "return document.body.dataset.ready && window.sloshPage.request.strategy === 'auto'"
                     " && document.querySelectorAll('#candidates tbody tr').length > 1")
    status, auto = api_json(port, "POST", "/v1/plans", request_of(THESIS, "auto"))
    check(status == 200, "the API plans auto")
    rows = table_rows(driver)
    names = [c["strategy"] for c in auto["candidates"]]
    check([r["strategy"] for r in rows] == names, f"one row per candidate of auto: {rows} vs {names}")
    chosen = [c["strategy"] for c in auto["candidates"] if c["chosen"]]
    check([r["strategy"] for r in rows if r["chosen"]] == chosen, f"the chosen row is highlighted ({chosen})")
    titles = driver.execute_script(
        "return [...document.querySelectorAll('#candidates tbody tr')].map(tr => tr.title)")
    expected_titles = ["" if c["chosen"] else f"auto did not choose it: {c['reason_detail']}"
                       for c in auto["candidates"]]
    check(titles == expected_titles, f"each row says why auto did not choose it: {titles}")
    for row in rows:
        _, plan = api_json(port, "POST", "/v1/plans", request_of(THESIS, row["strategy"]))
        check(row["cells"] == expected_row(plan), f"row {row['strategy']} equals its plan")
    driver.set_window_size(1280, 2300)
    driver.save_screenshot(screenshot)
    driver.set_window_size(1280, 800)
    # Selecting another row plots that candidate.
    other = next(r["strategy"] for r in rows if not r["chosen"])
    driver.find_element(By.CSS_SELECTOR, f"#candidates tr[data-strategy='{other}']").click()
    wait_for(driver, f"return document.body.dataset.ready === '{other}'")
    check(all(sum(c["counts"]) > 0 for c in chart_counts(driver)), "the selected candidate is plotted")


def min_time_request_of(values, strategies=None):
    body = {"format": request_of(dict(values, height=values["height"] or "0"), "baseline")["format"]}
    del body["format"]["motion_time_s"]
    if not values["height"]:
        del body["format"]["container"]["height_mm"]
    if strategies:
        body["strategies"] = strategies
    body["options"] = {}
    return body


def eta_at_t_min(s, quantity, model):
    if s["t_min_s"] is None or s["t_min_s"] not in s["curve"]["t_s"]:
        return None
    i = s["curve"]["t_s"].index(s["t_min_s"])
    nl, lin = s["curve"]["nonlinear"][quantity][i], s["curve"]["linear"][quantity][i]
    return lin if model == "linear" else max(nl, lin) if model == "both" else nl


def expected_min_time_row(s, model):
    above = "—" if s["feasible_above"] is None else "yes" if s["feasible_above"] else "no"
    return [s["strategy"], s["status"], fmt(s["t_min_s"], 3),
            fmt(None if s["t_min_s"] is None else 60 / s["t_min_s"], 1), above,
            fmt(eta_at_t_min(s, "eta_motion_mm", model)), fmt(eta_at_t_min(s, "eta_rest_mm", model)),
            str(s["plans"])]


def expected_headline(m):
    h = m["headline"]
    if h["winner"] is None:
        return f"No strategy meets the limits with a motion time up to {m['motion_time_max_s']:g} s."
    text = f"Fastest: {h['winner']}, T_min {h['t_min_s']:.3f} s ({h['cycles_per_min']:.1f} cycles/min)"
    if h["gain_pct"] is not None:
        text += (f": {h['gain_pct']:+.1f} % ({h['gain_cycles_per_min']:+.1f} cycles/min) vs the uniform law"
                 f" (baseline, T_min {h['baseline_t_min_s']:.3f} s, {h['baseline_cycles_per_min']:.1f} cycles/min).")
    elif any(s["strategy"] == "baseline" for s in m["strategies"]):
        text += "; the uniform law (baseline) meets the limits nowhere in the search: no gain to give."
    else:
        text += "; the uniform law (baseline) was not searched: no gain to give."
    return text


def min_time_rows(driver):
    return driver.execute_script(
        "return [...document.querySelectorAll('#min-time-table tbody tr')].map(tr => "
        "({strategy: tr.dataset.strategy, winner: tr.classList.contains('winner'), "
        "weight: getComputedStyle(tr).fontWeight, cells: [...tr.children].map(td => td.textContent)}))")


def min_time_charts(driver):
    return driver.execute_script(
        "return window.sloshPage.minTimeCharts.map(c => ({id: c.canvas.id, "
        "curves: Object.fromEntries(c.data.datasets.map(d => [d.strategy, d.data.length])), "
        "hlines: c.options.plugins.markers.hlines.map(h => h.y), "
        "vlines: c.options.plugins.markers.vlines.map(v => v.x)}))")


def check_min_time_view(driver, m, what):
    """The min-time table, headline and charts of the page equal the API's answer m."""
    check(driver.execute_script("return window.sloshPage.minTime.key") == m["key"],
          f"{what}: the page asked the API's request (same key)")
    rows = min_time_rows(driver)
    model = m["limits"]["model"]
    expected = [expected_min_time_row(s, model) for s in m["strategies"]]
    check([r["cells"] for r in rows] == expected, f"{what}: the min-time table equals the API: {rows} vs {expected}")
    winner = m["headline"]["winner"]
    check([r["strategy"] for r in rows if r["winner"]] == ([winner] if winner else []),
          f"{what}: the winner's row is marked ({winner})")
    check(all((r["weight"] == "700") == r["winner"] for r in rows), f"{what}: only the winner is bold: {rows}")
    headline = driver.find_element(By.ID, "min-time-headline").text
    check(headline == expected_headline(m), f"{what}: headline {headline!r} vs {expected_headline(m)!r}")
    charts = {c["id"]: c for c in min_time_charts(driver)}
    curves = {s["strategy"]: len(s["curve"]["t_s"]) for s in m["strategies"]}
    limits = {"plot-min-time-motion": m["limits"]["eta_motion_max_mm"],
              "plot-min-time-rest": m["limits"]["eta_rest_max_mm"]}
    check(sorted(charts) == sorted(limits), f"{what}: the two η-over-T charts: {sorted(charts)}")
    for chart_id, limit in limits.items():
        c = charts.get(chart_id, {})
        check(c.get("curves") == curves, f"{what}: {chart_id} holds the API's curves: {c} vs {curves}")
        check(c.get("hlines") == [limit], f"{what}: {chart_id} draws the limit {limit}: {c}")
        check(c.get("vlines") == ([m["headline"]["t_min_s"]] if winner else []), f"{what}: {chart_id} marks T_min")


def check_min_time(driver, port, screenshot):
    fill_format(driver, THESIS, "auto")
    driver.find_element(By.ID, "min-time-button").click()
    wait_for(driver, "return document.body.dataset.minTime === 'ready'", 120)
    status, m = api_json(port, "POST", "/v1/min-time", min_time_request_of(THESIS))
    check(status == 200 and len(m["strategies"]) == 7, f"the API searches every strategy but iir ({status})")
    check_min_time_view(driver, m, "auto")
    check(m["headline"]["gain_pct"] is not None, "the thesis format has a gain over the uniform law")
    check("mintime=1" in driver.current_url, f"the URL holds the min-time view: {driver.current_url}")
    driver.set_window_size(1280, 1260)
    driver.execute_script("window.scrollTo(0, 0)")
    driver.find_element(By.ID, "results").screenshot(screenshot)  # the min-time view
    driver.set_window_size(1280, 800)
    # A row loads its plan at T_min (the response's own plan) into the plan view.
    row = next(s for s in m["strategies"] if s["strategy"] == "shaper")
    driver.find_element(By.CSS_SELECTOR, "#min-time-table tr[data-strategy='shaper']").click()
    wait_for(driver, "return document.body.dataset.ready === 'shaper'")
    check(table_rows(driver)[0]["cells"] == expected_row(row["plan"]), "the row's plan at T_min is in the plan view")
    check(abs(row["plan"]["format"]["motion_time_s"] - row["t_min_s"]) < 1e-9, "the plan is at T_min")
    counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
    check(len(counts) == 5 and all(sum(v) > 0 for v in counts.values()), f"the plan at T_min is plotted: {counts}")
    check(len(min_time_charts(driver)) == 2, "the min-time charts stay beside the plan")
    # A shared min-time link of one strategy reproduces its search.
    driver.get(f"http://127.0.0.1:{port}/?r=48.5&h=150&fill=82&fluid=water&stroke=800&T=1"
               "&strategy=fir_chain&mintime=1")
    wait_for(driver, "return document.body.dataset.minTime === 'ready'")
    status, one = api_json(port, "POST", "/v1/min-time", min_time_request_of(THESIS, ["fir_chain"]))
    check(status == 200, f"the API searches fir_chain ({status})")
    check_min_time_view(driver, one, "fir_chain link")


def check_min_time_errors(driver, port):
    # Without a container height the min-time search needs eta_motion_max_mm (an advanced input).
    no_height = dict(THESIS, height="")
    fill_format(driver, no_height, "fir_chain")
    driver.find_element(By.ID, "min-time-button").click()
    wait_for(driver, "return document.getElementById('eta_motion_max-error').textContent.length > 0", 20)
    status, error = api_json(port, "POST", "/v1/min-time", min_time_request_of(no_height, ["fir_chain"]))
    check(status == 422 and error["error"]["field"] == "eta_motion_max_mm", f"the API needs eta_motion_max_mm: {error}")
    shown = driver.find_element(By.ID, "eta_motion_max-error").text
    check(shown == error["error"]["message"], f"the η motion limit field shows the API's message: {shown!r}")
    check(driver.find_element(By.ID, "eta_motion_max").get_attribute("aria-invalid") == "true",
          "the η motion limit input is marked invalid")
    check(not driver.find_element(By.ID, "min-time").is_displayed(), "no min-time view under a refused request")
    check(driver.execute_script("return window.sloshPage.minTimeCharts.length") == 0, "no min-time charts")
    # The search's own bound has its own input.
    fill_format(driver, THESIS, "fir_chain")
    driver.find_element(By.ID, "t_max").send_keys("100")
    driver.find_element(By.ID, "min-time-button").click()
    wait_for(driver, "return document.getElementById('t_max-error').textContent.length > 0", 20)
    body = dict(min_time_request_of(THESIS, ["fir_chain"]), motion_time_max_s=100)
    status, error = api_json(port, "POST", "/v1/min-time", body)
    check(status == 422 and error["error"]["field"] == "motion_time_max_s", f"the API refuses the bound: {error}")
    check(driver.find_element(By.ID, "t_max-error").text == error["error"]["message"],
          "the search bound field shows the API's message")
    driver.find_element(By.ID, "t_max").clear()


def check_invalid_radius(driver, port):
    bad = dict(THESIS, radius="-5")
    fill_format(driver, bad, "notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.getElementById('radius-error').textContent.length > 0", 20)
    status, error = api_json(port, "POST", "/v1/plans", request_of(bad, "notch"))
    check(status == 422 and error["error"]["field"] == "format.container.radius_mm",
          f"the API refuses the radius: {error}")
    shown = driver.find_element(By.ID, "radius-error").text
    check(shown == error["error"]["message"], f"the radius field shows the API's message: {shown!r}")
    check(driver.find_element(By.ID, "radius").get_attribute("aria-invalid") == "true",
          "the radius input is marked invalid")
    # Nothing of the previous view stays under the refused request.
    check(not driver.find_element(By.ID, "candidates").is_displayed(), "the old table is gone")
    check(chart_counts(driver) == [], "the old charts are gone")
    check(not driver.find_element(By.ID, "downloads").is_displayed(), "the old downloads are gone")


def check_shared_url(driver, plan):
    fill_format(driver, THESIS, "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch'")
    link = driver.find_element(By.ID, "share-link").get_attribute("href")
    fresh = browser()
    try:
        fresh.get(link)
        wait_for(fresh, "return document.body.dataset.ready === 'multi_notch'")
        check(table_rows(fresh)[0]["cells"] == expected_row(plan), "the shared URL reproduces the table")
        check(chart_counts(fresh) == chart_counts(driver), "the shared URL reproduces the charts")
    finally:
        fresh.quit()


def check_cam_download(driver, slosh, workdir):
    cam_period = driver.find_element(By.ID, "cam-period")
    cam_period.clear()
    cam_period.send_keys("2")
    href = driver.find_element(By.ID, "download-cam").get_attribute("href")
    downloaded = urllib.request.urlopen(href, timeout=60).read()
    request = os.path.join(workdir, "thesis.json")
    with open(request, "w") as f:
        json.dump(request_of(THESIS, "multi_notch"), f)
    out = os.path.join(workdir, "cam.csv")
    done = subprocess.run([slosh, "export", "--request", request, "--out", out, "--period-ms", "2",
                           "--cache", ""], capture_output=True, text=True)
    check(done.returncode == 0, f"slosh export ran: {done.stderr}")
    check(downloaded == open(out, "rb").read(), "the cam-table download equals slosh export's file")
    check(downloaded.startswith(b"t_s,position_mm"), "the download is the cam table")


def check_infeasible_cam_link(driver, port):
    values = dict(THESIS)
    fill_format(driver, values, "notch")
    driver.find_element(By.ID, "a_max").send_keys("1")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'notch'")
    driver.find_element(By.ID, "a_max").clear()
    link = driver.find_element(By.ID, "download-cam")
    href = link.get_attribute("href")
    check("allow_infeasible=true" in href and "infeasible" in link.text,
          f"an infeasible plan's cam link says what it exports: {link.text} {href}")
    check(urllib.request.urlopen(href, timeout=60).status == 200, "the infeasible plan's cam table downloads")


def planned(port, request, what):
    """The API's plan of `request` (checked to be 200, `what` naming it), or None."""
    status, plan = api_json(port, "POST", "/v1/plans", request)
    check(status == 200, f"the API plans {what} ({status}: {plan})")
    return plan if status == 200 else None


def check_key_view_custom_fluid(port):
    """A plan whose custom fluid carries a catalogue name but other properties is refilled as a
    custom fluid with its own density and viscosity, and replanned with them."""
    request = request_of(THESIS, "notch")
    request["format"]["fluid"] = {"name": "water", "density_kg_m3": 1260, "viscosity_pa_s": 1.4}
    plan = planned(port, request, "the custom fluid")
    if plan is None:
        return
    driver = browser()
    try:
        driver.get(f"http://127.0.0.1:{port}/?key={plan['key']}")
        wait_for(driver, "return document.body.dataset.ready === 'notch'")
        check(driver.find_element(By.ID, "fluid").get_attribute("value") == "custom",
              "the fluid is custom, not catalogue water")
        check(driver.find_element(By.ID, "density").get_attribute("value") == "1260" and
              driver.find_element(By.ID, "viscosity").get_attribute("value") == "1.4",
              "the custom inputs hold the plan's density and viscosity")
        check(driver.find_element(By.ID, "custom-fluid").is_displayed(), "the custom inputs are shown")
        driver.find_element(By.ID, "plan-button").click()
        wait_for(driver, "return document.body.dataset.ready === 'notch' && "
                         "window.sloshPage.request !== null && window.sloshPage.request.format !== undefined")
        fluid = driver.execute_script("return window.sloshPage.plans.notch.format.fluid")
        check(fluid["density_kg_m3"] == 1260 and fluid["viscosity_pa_s"] == 1.4,
              f"the replanned format keeps the fluid: {fluid}")
    finally:
        driver.quit()


def check_key_view_explicit_damping(port):
    """A plan made with an explicit damping ratio ({"zeta": z}) is opened by key and its plots
    are computed: the page asks simulate for that damping in the form the API takes."""
    request = request_of(THESIS, "notch")
    request["options"] = {"damping": {"zeta": 0.02}}
    plan = planned(port, request, "an explicit damping")
    if plan is None:
        return
    driver = browser()
    try:
        driver.get(f"http://127.0.0.1:{port}/?key={plan['key']}")
        wait_for(driver, "return document.body.dataset.ready === 'notch' || "
                         "document.getElementById('form-error').textContent !== ''")
        error = driver.find_element(By.ID, "form-error").text
        check(error == "", f"the plots of an explicit damping are computed: {error!r}")
        check(driver.execute_script("return document.body.dataset.ready") == "notch",
              "the plan opened by key is drawn")
    finally:
        driver.quit()


def check_key_view(port, plan):
    driver = browser()
    try:
        driver.get(f"http://127.0.0.1:{port}/?key={plan['key']}")
        wait_for(driver, f"return document.body.dataset.ready === '{plan['strategy']}'")
        check(driver.find_element(By.ID, "radius").get_attribute("value") == "48.5"
              and driver.find_element(By.ID, "stroke").get_attribute("value") == "800",
              "a plan opened by key fills the form with its format")
        check(driver.find_element(By.ID, "share-link").get_attribute("href").endswith(f"?key={plan['key']}"),
              "the link of a key view is the key")
        check(table_rows(driver)[0]["cells"] == expected_row(plan), "the key view shows the plan")
    finally:
        driver.quit()


def check_bad_link(port):
    driver = browser()
    try:
        driver.get(f"http://127.0.0.1:{port}/?r=48.5&h=150&fill=82&fluid=mercury&stroke=800&T=1&strategy=notch")
        wait_for(driver, "return document.body.dataset.loaded === '1'")
        error = driver.find_element(By.ID, "form-error").text
        check("fluid=mercury" in error, f"a link with an unknown fluid says so: {error!r}")
        check(table_rows(driver) == [], "a link the form cannot hold plans nothing")
    finally:
        driver.quit()


def check_labels(driver):
    unlabeled = driver.execute_script(
        "return [...document.querySelectorAll('input, select')].filter(e => "
        "!document.querySelector(`label[for='${e.id}']`)).map(e => e.id || e.name)")
    check(unlabeled == [], f"every input has a label: {unlabeled}")


def check_measured_overlay(driver, workdir):
    """A measured eta(t) CSV uploaded after a plan is drawn as points on the eta plot;
    a series whose times do not increase is refused with the line named."""
    path = os.path.join(workdir, "measured.csv")
    samples = [(0.01 * i, round(5.0 * (i % 20) - 40.0, 3)) for i in range(150)]
    with open(path, "w", encoding="utf-8") as f:
        f.write("t_s,eta_mm\n" + "".join(f"{t:.2f},{e}\n" for t, e in samples))
    driver.find_element(By.ID, "measured-csv").send_keys(path)
    wait_for(driver, "return document.body.dataset.measured === '150'")
    counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
    eta = counts.get("plot-eta", [])
    check(len(eta) == 5 and eta[4] == 150, f"the measured series is the 5th eta dataset: {counts}")
    label, x, y = driver.execute_script(
        "const c = window.sloshPage.charts.find(c => c.canvas.id === 'plot-eta');"
        "const d = c.data.datasets[4]; return [d.label, d.data[3].x, d.data[3].y];")
    check(label == "η measured" and abs(x - 0.03) < 1e-12 and y == samples[3][1],
          f"measured point 3 is ({x}, {y}) labelled {label}")
    bad = os.path.join(workdir, "bad.csv")
    with open(bad, "w", encoding="utf-8") as f:
        f.write("t_s,eta_mm\n0,1\n0,2\n")
    driver.find_element(By.ID, "measured-csv").send_keys(bad)
    wait_for(driver, "return document.body.dataset.measured === 'invalid'")
    note = driver.find_element(By.ID, "measured-note").text
    check(note == "bad.csv is not a series: line 3: t_s = 0 is not after 0: times must increase",
          f"the refusal names the line: {note}")
    counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
    check(len(counts.get("plot-eta", [])) == 4, f"no overlay after a refused file: {counts}")


# A fetch wrapper that holds back the answers of the requests `predicate_js` picks (a JS
# expression of `input`, `init` and `body`, the request's JSON text) until window.__release(). By
# default (LATE_ANSWER) the request itself is sent and answered at once, its abort signal ignored,
# so the page gets a complete, late answer even after it aborted the fetch, and must drop it.
# window.__held counts the held requests; window.__delivered those whose JSON the page has read
# and acted on; window.__aborted those ABORTABLE rejected.
def hold_fetch(predicate_js, held=None):
    return """
window.__realFetch = window.__realFetch || window.fetch;
const real = window.__realFetch;
let release;
const gate = new Promise((resolve) => { release = resolve; });
window.__held = 0;
window.__delivered = 0;
window.__aborted = 0;
window.__release = release;
window.fetch = async (input, init) => {
  const body = init && typeof init.body === 'string' ? init.body : '';
  if (!(PREDICATE)) return real(input, init);
  window.__held++;
HELD};
""".replace("PREDICATE", predicate_js).replace("HELD", held or LATE_ANSWER)


LATE_ANSWER = """
  const res = await real(input, { ...init, signal: undefined });
  await gate;
  // Counted once the page has its JSON and has run what follows (microtasks before this task).
  const json = res.json.bind(res);
  res.json = async () => {
    const value = await json();
    setTimeout(() => { window.__delivered++; }, 0);
    return value;
  };
  return res;
"""

# The held request waits for window.__release() before it is sent, and an abort of its signal
# while it waits rejects it with the signal's reason, as a fetch aborted on a slow network does.
ABORTABLE = """
  const signal = init && init.signal;
  await new Promise((resolve, reject) => {
    gate.then(resolve);
    if (signal) signal.addEventListener('abort', () => { window.__aborted++; reject(signal.reason); });
  });
  return real(input, init);
"""


# The v1/simulate requests of plans whose motion time is 1.5 s: an earlier request that answers
# after a later one.
HOLD_SLOW_SERIES = hold_fetch(
    """String(input).endsWith('v1/simulate') && body.includes('"motion_time_s":1.5')""")


def chart_data(driver):
    return driver.execute_script(
        "return Object.fromEntries(window.sloshPage.charts.map(c => [c.canvas.id, "
        "c.data.datasets.map(d => d.data.map(p => [p.x, p.y]))]))")


def check_shows_plan(driver, plan):
    """The table, the status line and the plan download are those of `plan` (a notch plan of the
    later request, after an earlier request's late answer was dropped)."""
    check(table_rows(driver)[0]["cells"] == expected_row(plan), "the table shows the later plan")
    line = driver.find_element(By.ID, "status-line").text
    check(line == f"notch: {plan['status']}. {plan['message']}", f"the status line is the later plan's: {line}")
    check(driver.find_element(By.ID, "download-json").get_attribute("download") == f"plan-{plan['key']}.json",
          "the plan download is the later plan")


def plan_later_then_release(driver, port, held=1):
    """With `held` answers of an earlier request held: plans notch on the thesis format (T = 1 s),
    waits for it to be drawn, releases the held answers and waits for the page to have handled
    them. Returns the API's plan of the later request."""
    fill_format(driver, THESIS, "notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'notch' && "
                     "window.sloshPage.plans.notch.format.motion_time_s === 1")
    driver.execute_script("window.__release()")
    wait_for(driver, f"return window.__delivered === {held}")  # the late answers were handled
    status, plan = api_json(port, "POST", "/v1/plans", request_of(THESIS, "notch"))
    check(status == 200, f"the API plans notch ({status})")
    return plan


def check_keeps_later_plan(driver, plan):
    """The page's plans, table, status line and downloads are the later `plan`, with no error."""
    check(driver.execute_script("return Object.keys(window.sloshPage.plans)") == ["notch"] and
          driver.execute_script("return window.sloshPage.plans.notch.key") == plan["key"],
          "the page's plans are the later plan")
    check_shows_plan(driver, plan)
    check(driver.find_element(By.ID, "form-error").text == "", "no error from the dropped answer")


def check_late_answer(driver, port):
    """The plots of an earlier request that answer after a later request's are dropped: the
    table, the status line, the URL, the downloads and every plot show the later plan."""
    driver.execute_script(HOLD_SLOW_SERIES)
    fill_format(driver, dict(THESIS, time="1.5"), "notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return window.__held === 2")  # the first plan's two series are held
    plan = plan_later_then_release(driver, port, held=2)
    check_shows_plan(driver, plan)
    check("T=1&" in driver.current_url, f"the URL is the later request's: {driver.current_url}")
    check(f"/v1/plans/{plan['key']}/cam.csv" in driver.find_element(By.ID, "download-cam").get_attribute("href"),
          "the cam link is the later plan's")
    check(driver.execute_script("return window.sloshPage.plotContext.plan.key") == plan["key"],
          "the plot context is the later plan")
    body = {"format": plan["format"], "law": plan["law"], "rest_time_s": plan["rest_time_s"],
            "options": {"damping": plan["model"]["damping"], "alpha": plan["model"]["alpha"],
                        "modes": len(plan["model"]["f_hz"]), "min_ramp_s": 0.001},
            "sample_period_s": (plan["format"]["motion_time_s"] + plan["rest_time_s"]) / 2000}
    series = api_json(port, "POST", "/v1/simulate", body)[1]["series"]
    data = chart_data(driver)
    expected = {
        "plot-acceleration": [[t, a] for t, a in zip(series["t_s"], series["a"])],
        "plot-velocity": [[t, v] for t, v in zip(series["t_s"], series["v"])],
        "plot-eta": [[t, e] for t, e in zip(series["t_s"], series["eta_nonlinear_mm"])],
        "plot-spectrum": [[f, x] for f, x in zip(plan["spectrum"]["f_hz"], plan["spectrum"]["amplitude"])],
        "plot-robustness": [[p["delta_pct"], p["nonlinear"]["eta_rest_mm"] if p["nonlinear"] else None]
                            for p in plan["robustness"]["points"]],
    }
    check(sorted(data) == sorted(expected), f"the five plots: {sorted(data)}")
    for chart_id, points in expected.items():
        check(data.get(chart_id, [[]])[0] == points, f"{chart_id} shows the later plan's first curve")
    driver.execute_script("window.fetch = window.__realFetch")


# GET v1/plans/<window.__heldKey> (installed before the page's own script runs, so the page's
# opening of ?key= is held).
HOLD_KEY_ANSWER = hold_fetch(
    "(!init || !init.method || init.method === 'GET') && window.__heldKey && "
    "String(input).endsWith('v1/plans/' + window.__heldKey)")


def check_late_key_answer(driver, port):
    """A plan opened by ?key= whose answer arrives after a later planned request is dropped: the
    form, the table, the status line and the URL keep the later plan."""
    status, early = api_json(port, "POST", "/v1/plans", request_of(dict(THESIS, time="1.5"), "notch"))
    check(status == 200, f"the API plans the early plan ({status})")
    script = driver.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {
        "source": f"window.__heldKey = {json.dumps(early['key'])};" + HOLD_KEY_ANSWER})
    try:
        driver.get(f"http://127.0.0.1:{port}/?key={early['key']}")
        wait_for(driver, "return document.body.dataset.loaded === '1' && window.__held === 1")
        plan = plan_later_then_release(driver, port)
        check(driver.find_element(By.ID, "time").get_attribute("value") == "1",
              "the form keeps the later request's motion time")
        check_keeps_later_plan(driver, plan)
        check("T=1&" in driver.current_url and "key=" not in driver.current_url,
              f"the URL is the later request's: {driver.current_url}")
    finally:
        driver.execute_cdp_cmd("Page.removeScriptToEvaluateOnNewDocument", script)
        driver.execute_script("window.fetch = window.__realFetch")


# Chart.js throwing after it registered its chart (as it does on an axis it cannot scale): the
# plot of `plot-eta` fails while the test's wrapper is installed.
BREAK_ETA_PLOT = """
window.__RealChart = window.__RealChart || window.Chart;
window.Chart = class extends window.__RealChart {
  constructor(canvas, config) {
    super(canvas, config);
    if (canvas.id === 'plot-eta') throw new RangeError('test: the axis cannot be scaled');
  }
};
"""


def live_charts(driver):
    return driver.execute_script("return Object.keys(Chart.instances).length")


def check_plot_error(driver):
    """A plot that cannot be drawn costs that plot only, says so, leaks no chart, and the next
    plan draws every plot."""
    driver.execute_script(BREAK_ETA_PLOT)
    fill_format(driver, THESIS, "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch'")
    ids = sorted(c["id"] for c in chart_counts(driver))
    check(ids == ["plot-acceleration", "plot-robustness", "plot-spectrum", "plot-velocity"],
          f"the other plots are drawn: {ids}")
    note = driver.execute_script(
        "const n = document.querySelector('#plots .plot-error'); return n && n.textContent")
    check(note == "This plot could not be drawn: test: the axis cannot be scaled", f"the plot says why: {note}")
    check(live_charts(driver) == 4, f"no chart leaks: {live_charts(driver)} live")
    driver.execute_script("window.Chart = window.__RealChart")
    fill_format(driver, dict(THESIS, stroke="700"), "multi_notch")
    driver.find_element(By.ID, "plan-button").click()
    wait_for(driver, "return document.body.dataset.ready === 'multi_notch' && "
                     "window.sloshPage.plotContext.plan.format.stroke_mm === 700")
    check(len(chart_counts(driver)) == 5, "the next plan draws every plot")
    check(live_charts(driver) == 5, f"no chart of the broken view is left: {live_charts(driver)} live")
    check(driver.execute_script("return document.querySelectorAll('#plots .plot-error').length") == 0,
          "the error went with its view")
    fill_format(driver, THESIS, "multi_notch")  # the form of the checks that follow


def upload_measured(driver, workdir, name, text):
    path = os.path.join(workdir, name)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    driver.execute_script("delete document.body.dataset.measured")
    driver.find_element(By.ID, "measured-csv").send_keys(path)
    wait_for(driver, "return document.body.dataset.measured !== undefined")
    return driver.find_element(By.ID, "measured-note").text


def check_measured_formats(driver, workdir):
    """A measured series is split on ';' (with decimal commas), else a tab, else ','; a header may
    follow blank lines; a third column, a hex number or a single sample is refused, named."""
    accepted = [
        ("semicolon.csv", "t_s;eta_mm\n0,00;0,5\n0,01;-1,25\n0,02;10,0\n1;2\n",
         {"t_s": [0.0, 0.01, 0.02, 1.0], "eta_mm": [0.5, -1.25, 10.0, 2.0]}),
        ("tab.csv", "\n\nt_s\teta_mm\n0\t1.5\n0.5\t-2e1\n",
         {"t_s": [0.0, 0.5], "eta_mm": [1.5, -20.0]}),
    ]
    for name, text, expected in accepted:
        note = upload_measured(driver, workdir, name, text)
        n = len(expected["t_s"])
        check(note == f"{name}: {n} samples overlaid on η(t)", f"{name} is read: {note!r}")
        got = driver.execute_script("return window.sloshPage.measured")
        check(got == expected, f"{name} holds {expected}: {got}")
    refused = [
        ("three.csv", "t_s,eta_mm\n0,1\n1,2,3\n",
         "three.csv is not a series: line 3: 3 values, expected 2: t_s, eta_mm"),
        ("hex.csv", "0x10,1\n17,2\n", 'hex.csv is not a series: line 1: t_s = "0x10" is not a decimal number'),
        ("hexeta.csv", "t_s,eta_mm\n0,1\n1,0x2\n",
         'hexeta.csv is not a series: line 3: eta_mm = "0x2" is not a decimal number'),
        ("one.csv", "\n\nt_s,eta_mm\n0,1\n", "one.csv is not a series: 1 sample: at least 2 are needed"),
        ("none.csv", "t_s,eta_mm\n", "none.csv is not a series: 0 samples: at least 2 are needed"),
    ]
    for name, text, expected in refused:
        note = upload_measured(driver, workdir, name, text)
        check(note == expected, f"{name} is refused: {note!r}")
        check(driver.execute_script("return document.body.dataset.measured") == "invalid", f"{name}: no overlay")


def check_measured_limits(driver, workdir):
    """A measured series beyond what a measurement holds is refused with its line, value and
    range (Chart.js cannot scale an axis to 1e308); the page keeps working."""
    cases = [
        ("huge.csv", "t_s,eta_mm\n0,1\n1,1.7e308\n",
         "huge.csv is not a series: line 3: eta_mm = 1.7e+308 is outside [-10000, 10000] mm"),
        ("wide.csv", "0,9e307\n1,-9e307\n",
         "wide.csv is not a series: line 1: eta_mm = 9e+307 is outside [-10000, 10000] mm"),
        ("long.csv", "0,1\n4000,2\n",
         "long.csv is not a series: line 2: t_s = 4000 is outside [-3600, 3600] s"),
        ("many.csv", "t_s,eta_mm\n" + "".join(f"{i * 1e-3:.3f},1\n" for i in range(100001)),
         "many.csv is not a series: line 100002: more than 100000 samples"),
    ]
    for name, text, expected in cases:
        note = upload_measured(driver, workdir, name, text)
        check(note == expected, f"{name} is refused: {note!r}")
        check(driver.execute_script("return document.body.dataset.measured") == "invalid", f"{name}: no overlay")
        counts = {c["id"]: c["counts"] for c in chart_counts(driver)}
        check(len(counts) == 5 and len(counts.get("plot-eta", [])) == 4, f"{name}: the plots stay: {counts}")
    note = upload_measured(driver, workdir, "fine.csv", "0,1\n0.5,-2\n1,3\n")
    check(note == "fine.csv: 3 samples overlaid on η(t)", f"a valid series after the refusals: {note!r}")
    check(live_charts(driver) == 5, f"no chart leaks over the uploads: {live_charts(driver)}")
    upload_measured(driver, workdir, "reset.csv", "0,1\n")  # refused: no overlay for what follows


def check_cam_refusal(driver, port, downloads):
    """A period the API refuses shows the API's message at the period input; nothing is saved.
    A valid period saves the cam table under its name."""
    period = driver.find_element(By.ID, "cam-period")
    period.clear()
    period.send_keys("-1")
    link = driver.find_element(By.ID, "download-cam")
    href = link.get_attribute("href")
    status, error = api_json(port, "GET", href[href.index("/v1/"):])
    check(status == 422 and error["error"]["field"] == "period_ms", f"the API refuses the period: {error}")
    link.click()
    wait_for(driver, "return document.getElementById('cam-period-error').textContent.length > 0", 20)
    shown = driver.find_element(By.ID, "cam-period-error").text
    check(shown == error["error"]["message"], f"the period shows the API's message: {shown!r}")
    check(period.get_attribute("aria-invalid") == "true", "the period input is marked invalid")
    time.sleep(1)
    check(os.listdir(downloads) == [], f"nothing saved for a refused period: {os.listdir(downloads)}")
    period.clear()
    period.send_keys("2")
    check(driver.find_element(By.ID, "cam-period-error").text == "", "a new period clears the message")
    name = link.get_attribute("download")
    link.click()
    path = os.path.join(downloads, name)
    end = time.time() + 30
    while time.time() < end and not os.path.exists(path):
        time.sleep(0.1)
    expected = urllib.request.urlopen(link.get_attribute("href"), timeout=60).read()
    check(os.path.exists(path) and open(path, "rb").read() == expected,
          f"the cam table is saved as {name}: {os.listdir(downloads)}")
    period.clear()
    period.send_keys("1")


def check_unreadable_period(driver, downloads):
    """A typed period the number input cannot read is refused at the input, never taken as the
    default 1 ms: the message is shown, the input marked, nothing saved."""
    period = driver.find_element(By.ID, "cam-period")
    link = driver.find_element(By.ID, "download-cam")
    expected = "the period is not a number: type a decimal number of milliseconds, such as 1 or 0.5"
    for typed in ("1e400", "--1", "5e"):
        before = sorted(os.listdir(downloads))
        period.clear()
        period.send_keys(typed)
        check(driver.execute_script("const p = document.getElementById('cam-period');"
                                    "return p.value === '' && p.validity.badInput"), f"{typed}: the input cannot read it")
        shown = driver.find_element(By.ID, "cam-period-error").text
        check(shown == expected, f"{typed}: the input says so: {shown!r}")
        link.click()
        time.sleep(1)
        shown = driver.find_element(By.ID, "cam-period-error").text
        check(shown == expected, f"{typed}: the click says so: {shown!r}")
        check(period.get_attribute("aria-invalid") == "true", f"{typed}: the period input is marked invalid")
        check(driver.find_element(By.ID, "cam-note").text == "", f"{typed}: no download under way")
        check(sorted(os.listdir(downloads)) == before, f"{typed}: nothing saved: {os.listdir(downloads)}")
    period.clear()
    period.send_keys("1")
    check(driver.find_element(By.ID, "cam-period-error").text == "", "a readable period clears the message")


# The inputs of each request as the page's form module lists them (the module instance the page
# runs): id, path in that request, what kind of input and, for a select, its option values.
PAGE_FIELDS = """
const done = arguments[arguments.length - 1];
import('./assets/form.js').then((m) => Object.fromEntries(['plan', 'min-time'].map((kind) => [kind,
  m.fieldsOf(kind).map(([el, path]) => ({
    id: el.id, path, tag: el.tagName, type: el.type, number: 'number' in el.dataset, shown: !el.closest('[hidden]'),
    options: el.tagName === 'SELECT' ? [...el.options].map((o) => o.value) : []}))])))
  .then(done, (e) => done(String(e)));
"""

REQUEST_SCHEMAS = {"plan": "PlanRequest", "min-time": "MinTimeRequest"}


def page_fields(driver):
    fields = driver.execute_async_script(PAGE_FIELDS)
    if not isinstance(fields, dict):
        raise RuntimeError(f"the page's form module did not load: {fields}")
    return fields


def schema_alternatives(doc, schema):
    """The schemas a schema stands for: its $ref followed, each alternative of a oneOf."""
    while "$ref" in schema:
        schema = doc["components"]["schemas"][schema["$ref"].rsplit("/", 1)[1]]
    if "oneOf" in schema:
        return [a for s in schema["oneOf"] for a in schema_alternatives(doc, s)]
    return [schema]


def schemas_at(doc, request, path):
    """The schemas of the member at `path` ("options.uncertainty.fill_height_mm[1]") of the request
    schema `request`; empty when the API has no such member (its request objects are closed)."""
    at = schema_alternatives(doc, doc["components"]["schemas"][request])
    for key in re.findall(r"\[\d+\]|[^.\[\]]+", path):
        found = []
        for s in at:
            if key.startswith("["):
                if s.get("type") == "array" and int(key[1:-1]) < s.get("maxItems", 1 << 30):
                    found += schema_alternatives(doc, s["items"])
            elif s.get("type") == "object" and key in s.get("properties", {}):
                found += schema_alternatives(doc, s["properties"][key])
        at = found
    return at


def takes(schemas, value, number):
    """Whether one of the schemas takes `value`, an option of a select, as the page sends it."""
    if value == "custom":  # the custom fluid: an object its group's inputs fill
        return any(s.get("type") == "object" for s in schemas)
    if number:
        return any(s.get("type") in ("number", "integer") and s.get("minimum", -1e308) <= float(value)
                   <= s.get("maximum", 1e308) for s in schemas)
    return any(s.get("type") == "string" and value in s.get("enum", [value]) for s in schemas)


def check_field_paths(driver, port):
    """Every data-field path (and min-time path) of the form is a member of the request schema the
    service publishes (GET /v1/openapi.json), of the type the input sends: a number for a number
    input, each option of a select an allowed value. Every input goes into some request."""
    status, doc = api_json(port, "GET", "/v1/openapi.json")
    check(status == 200, f"the service serves its OpenAPI document ({status})")
    fields = page_fields(driver)
    every = driver.execute_script("return [...document.querySelectorAll('[data-field]')].map(e => e.id)")
    listed = {f["id"] for kind in fields.values() for f in kind}
    check(sorted(listed) == sorted(every), f"every input goes into a request: {sorted(every)} vs {sorted(listed)}")
    only = {kind: {f["id"] for f in fields[kind]} - {f["id"] for f in fields[other]}
            for kind, other in (("plan", "min-time"), ("min-time", "plan"))}
    check(only == {"plan": {"time"}, "min-time": {"t_max", "margin", "limit_model"}},
          f"the motion time goes into the plan request only, the search's inputs into min-time only: {only}")
    for kind, request in REQUEST_SCHEMAS.items():
        for f in fields[kind]:
            schemas = schemas_at(doc, request, f["path"])
            if not schemas and f["path"].startswith("format.motion."):
                # The published request schemas give format.motion in SimulateFormat only (plans
                # take arcs and paths, min-time refuses them by name): its members are checked
                # against the Motion schema the service publishes for it.
                schemas = schemas_at(doc, "SimulateFormat", f["path"].removeprefix("format."))
            what = f"{kind}: #{f['id']} {f['path']}"
            check(schemas != [], f"{what} is a member of {request}")
            if f["type"] == "checkbox":
                check(any(s.get("type") == "boolean" for s in schemas), f"{what} is a checkbox of a boolean: {schemas}")
                continue
            if f["tag"] == "INPUT":
                check(f["type"] == "number" and any(s.get("type") in ("number", "integer") for s in schemas),
                      f"{what} is a number input of a number: {f['type']} {schemas}")
                continue
            for value in f["options"]:
                # "" sends nothing (the default); for the min-time request auto sends no strategies
                # (the service's default: every strategy but iir).
                if value == "" or (kind == "min-time" and f["id"] == "strategy" and value == "auto"):
                    continue
                check(takes(schemas, value, f["number"]), f"{what} takes its option {value!r}")


def placement(field, inputs):
    """The input an error naming `field` belongs at: the input of that path or of the longest path
    holding it; an error about a whole range at its first end's ([0]); an error about an object
    inside a top-level member that no input holds (a motion, a segment) at its first shown input;
    None: at the form."""
    best = None
    inside = None
    for f in inputs:
        p = f["path"]
        if p == field + "[0]":
            return f["id"]
        if (field == p or field.startswith(p + ".") or field.startswith(p + "[")) and \
                (best is None or len(p) > len(best["path"])):
            best = f
        if inside is None and re.search(r"[.\[]", field) and f["shown"] and \
                (p.startswith(field + ".") or p.startswith(field + "[")):
            inside = f
    best = best or inside
    return best and best["id"]


# An input given a value the API refuses (an added option for a select); a range end with its
# other end valid, a custom fluid member with the custom fluid chosen.
CORRUPT = """
const [id, other, otherValue] = arguments;
const el = document.getElementById(id);
if (el.tagName === 'SELECT') {
  const v = 'number' in el.dataset ? '7' : 'bogus';
  el.add(new Option(v, v));
  el.value = v;
} else {
  el.value = '-1e300';
}
if (other) document.getElementById(other).value = otherValue;
// The groups the input is in are shown (the custom fluid chosen, the arc or path, a rectangular
// container, an arc segment), outermost first.
const groups = [];
for (let g = el.closest('[data-when]'); g; g = g.parentElement.closest('[data-when]')) groups.unshift(g);
for (const g of groups) {
  const [select, value] = g.dataset.when.split('=');
  document.getElementById(select).value = value;
  document.getElementById(select).dispatchEvent(new Event('change', { bubbles: true }));
}
"""

OTHER_END = {"fill_min": ("fill_max", "90"), "fill_max": ("fill_min", "75"),
             "visc_min": ("visc_max", "0.002"), "visc_max": ("visc_min", "0.0005")}

# The request the form now holds, built by the page's own form module.
PAGE_REQUEST = """
const done = arguments[arguments.length - 1];
const kind = arguments[0];
import('./assets/form.js').then((m) => (kind === 'plan'
  ? m.planRequest(document.getElementById('strategy').value) : m.minTimeRequest()))
  .then(done, (e) => done(String(e)));
"""


def check_errors_at_fields(driver, port):
    """For every input, a value the API refuses: the API's error (the page's own request posted
    again) names the input's path, and the page shows its message next to the input its field
    names (marked aria-invalid), nowhere else. Plan inputs through Plan; the inputs whose path
    differs in the min-time request, and its own, through "How fast can it go?"."""
    base = f"http://127.0.0.1:{port}/"
    driver.get(base)
    wait_for(driver, "return document.body.dataset.loaded === '1'")
    fields = page_fields(driver)
    plan_paths = {f["id"]: f["path"] for f in fields["plan"]}
    # A checkbox sends true or false, both taken: it has no value to refuse.
    cases = [("plan", f) for f in fields["plan"] if f["type"] != "checkbox"] + \
        [("min-time", f) for f in fields["min-time"] if plan_paths.get(f["id"]) != f["path"]]
    check(len([c for c in cases if c[0] == "min-time"]) == 6, f"six min-time inputs of their own: {cases}")
    for kind, f in cases:
        driver.get(base)
        wait_for(driver, "return document.body.dataset.loaded === '1'")
        driver.execute_script(CORRUPT, f["id"], *OTHER_END.get(f["id"], (None, None)))
        driver.find_element(By.ID, "plan-button" if kind == "plan" else "min-time-button").click()
        wait_for(driver, "return document.getElementById('status-line').textContent.startsWith('The service refused')"
                         " || document.getElementById('form-error').textContent"
                         " || document.body.dataset.ready || document.body.dataset.minTime", 30)
        request = driver.execute_async_script(PAGE_REQUEST, kind)
        what = f"{kind}: #{f['id']} ({f['path']})"
        check(isinstance(request, dict), f"{what}: the page builds its request: {request}")
        if not isinstance(request, dict):
            continue
        status, error = api_json(port, "POST", "/v1/plans" if kind == "plan" else "/v1/min-time", request)
        check(status == 422, f"{what}: the API refuses {request}: {status} {error}")
        if status != 422:
            continue
        field, message = error["error"]["field"], error["error"]["message"]
        own = f["path"].removesuffix("[0]").removesuffix("[1]")
        check(field == own or field.startswith(own + ".") or field.startswith(own + "["),
              f"{what}: the API names the input's path: {field}")
        expected = placement(field, page_fields(driver)[kind])  # the groups shown now
        shown = driver.execute_script(
            "return [...document.querySelectorAll('[aria-invalid]')].map(e => e.id)")
        check(shown == [expected], f"{what}: the error of {field} is at #{expected}: marked {shown}")
        texts = driver.execute_script(
            "return Object.fromEntries([...document.querySelectorAll('.field-error, .form-error')]"
            ".filter(e => e.textContent).map(e => [e.id, e.textContent]))")
        check(texts == {f"{expected}-error": message}, f"{what}: the API's message next to #{expected}: {texts}")


def check_late_plan_answer(driver, port):
    """The plan of an earlier Plan that answers after a later Plan's is dropped: the page's plans,
    request, table, status line, URL and downloads stay the later plan's, and no error shows."""
    driver.execute_script(hold_fetch(
        """String(input).endsWith('v1/plans') && body.includes('"motion_time_s":1.5')"""))
    try:
        fill_format(driver, dict(THESIS, time="1.5"), "notch")
        driver.find_element(By.ID, "plan-button").click()
        wait_for(driver, "return window.__held === 1")
        plan = plan_later_then_release(driver, port)
        check(driver.execute_script("return window.sloshPage.request.format.motion_time_s") == 1,
              "the page's request is the later one")
        check_keeps_later_plan(driver, plan)
        check("T=1&" in driver.current_url, f"the URL is the later request's: {driver.current_url}")
    finally:
        driver.execute_script("window.fetch = window.__realFetch")


def check_late_min_time_answer(driver, port):
    """A min-time search that answers after a later Plan is drawn is dropped: no min-time view,
    no min-time answer kept, and the plan view, URL and status line stay the later plan's."""
    driver.execute_script(hold_fetch("String(input).endsWith('v1/min-time')"))
    try:
        fill_format(driver, THESIS, "fir_chain")
        driver.find_element(By.ID, "min-time-button").click()
        wait_for(driver, "return window.__held === 1")
        plan = plan_later_then_release(driver, port)
        check(not driver.find_element(By.ID, "min-time").is_displayed(), "no min-time view from the late answer")
        check(driver.execute_script("return window.sloshPage.minTime") is None and
              driver.execute_script("return document.body.dataset.minTime") is None,
              "no min-time answer kept")
        check_keeps_later_plan(driver, plan)
        check("mintime" not in driver.current_url, f"the URL is the later request's: {driver.current_url}")
    finally:
        driver.execute_script("window.fetch = window.__realFetch")


def check_aborted_request_shows_no_error(driver, port):
    """A min-time search still waiting for its answer when Plan is pressed is aborted (its fetch
    rejects with an AbortError) and shows no error: no field marked, no message, the status line
    and the view are the plan's, no min-time view."""
    driver.execute_script(hold_fetch("String(input).endsWith('v1/min-time')", ABORTABLE))
    try:
        fill_format(driver, THESIS, "fir_chain")
        driver.find_element(By.ID, "min-time-button").click()
        wait_for(driver, "return window.__held === 1")
        Select(driver.find_element(By.ID, "strategy")).select_by_value("notch")
        driver.find_element(By.ID, "plan-button").click()
        # The abort rejected the held fetch before the plan was drawn: a page that showed the
        # aborted request's error shows it by now.
        wait_for(driver, "return document.body.dataset.ready === 'notch' && window.__aborted === 1")
        status, plan = api_json(port, "POST", "/v1/plans", request_of(THESIS, "notch"))
        check(status == 200, f"the API plans notch ({status})")
        texts = driver.execute_script(
            "return [...document.querySelectorAll('.field-error, .form-error')].map(e => e.textContent).join('')")
        check(texts == "", f"no error from the aborted search: {texts!r}")
        check(driver.execute_script("return document.querySelectorAll('[aria-invalid]').length") == 0,
              "no input marked by the aborted search")
        check(not driver.find_element(By.ID, "min-time").is_displayed(), "no min-time view")
        check(driver.execute_script("return window.sloshPage.minTime") is None, "no min-time answer kept")
        check_shows_plan(driver, plan)
    finally:
        driver.execute_script("window.fetch = window.__realFetch")


def check_sub_path(port):
    proxy = SubPathProxy(port)
    thread = threading.Thread(target=proxy.serve_forever, daemon=True)
    thread.start()
    driver = browser()
    try:
        driver.get(f"http://127.0.0.1:{proxy.server_address[1]}/slosh/?r=48.5&h=150&fill=82&fluid=water"
                   "&stroke=800&T=1&strategy=notch")
        wait_for(driver, "return document.body.dataset.ready === 'notch'")
        check(len(table_rows(driver)) == 1, "behind a proxy at /slosh/ the page plans")
    finally:
        driver.quit()
        proxy.shutdown()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--slosh", required=True)
    parser.add_argument("--artifacts", required=True)
    args = parser.parse_args()
    os.makedirs(args.artifacts, exist_ok=True)
    workdir = tempfile.mkdtemp(prefix="slosh-browser-")
    server, port = start_server(args.slosh, workdir)
    downloads = os.path.join(workdir, "downloads")
    os.makedirs(downloads)
    driver = browser(downloads)
    try:
        driver.get(f"http://127.0.0.1:{port}/")
        wait_for(driver, "return document.body.dataset.loaded === '1'")
        check_labels(driver)
        check(not driver.find_element(By.ID, "downloads").is_displayed(), "no downloads before a plan")
        plan = check_single_plan(driver, port)
        check_measured_overlay(driver, workdir)
        check_measured_limits(driver, workdir)
        check_measured_formats(driver, workdir)
        check_cam_download(driver, args.slosh, workdir)
        check_cam_refusal(driver, port, downloads)
        check_unreadable_period(driver, downloads)
        check_late_answer(driver, port)
        check_late_key_answer(driver, port)
        check_late_plan_answer(driver, port)
        check_late_min_time_answer(driver, port)
        check_aborted_request_shows_no_error(driver, port)
        check_plot_error(driver)
        check_compare_all(driver, port, os.path.join(args.artifacts, "page.png"))
        check_min_time(driver, port, os.path.join(args.artifacts, "min-time.png"))
        check_min_time_errors(driver, port)
        check_invalid_radius(driver, port)
        check_shared_url(driver, plan)
        check_infeasible_cam_link(driver, port)
        check_uncertainty(driver, port)
        motion_checks.run(driver, port, {
            "check": check, "api_json": api_json, "wait_for": wait_for, "expected_row": expected_row,
            "table_rows": table_rows, "chart_counts": chart_counts, "browser": browser,
            "artifacts": args.artifacts})
        check_field_paths(driver, port)
        check_errors_at_fields(driver, port)
        check_key_view(port, plan)
        check_key_view_custom_fluid(port)
        check_key_view_explicit_damping(port)
        check_bad_link(port)
        check_sub_path(port)
        severe = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"
                  and "422" not in e["message"]]
        check(severe == [], f"no errors in the browser console: {severe}")
    finally:
        driver.quit()
        server.terminate()
        server.wait(timeout=30)
        shutil.rmtree(workdir, ignore_errors=True)
    if FAILURES:
        print(f"{len(FAILURES)} check(s) failed")
        return 1
    print("browser page: all checks passed; screenshots in", os.path.join(args.artifacts, "page.png"), "and",
          os.path.join(args.artifacts, "min-time.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
