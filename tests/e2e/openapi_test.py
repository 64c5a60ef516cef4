#!/usr/bin/env python3
"""Validates the live daemon's answers against docs/openapi.yaml.

Starts the real `rollwear serve` on a temporary SQLite file with a token,
replays a small simulated dataset through it, then calls every operation of
the OpenAPI file - each documented success and a representative set of
errors - and checks for every answer that its status code is listed for
that operation and its body validates against the listed schema (JSON
Schema 2020-12, python3-jsonschema). Fails when an operation of the file
was never answered with a 2xx, or when a path the daemon serves is not in
the file.

The daemon's own list of routes is read from its route table,
api/router_routes.cc (each endpoint declared once, with its method and path
pattern): every one must be in the file.

Usage: openapi_test.py --rollwear BIN --spec docs/openapi.yaml
                       --routes api/router_routes.cc
Run by ctest as `openapi_test` (tests/CMakeLists.txt).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

import jsonschema
import yaml

TOKEN = "openapi-test-token"


class Spec:
    """The OpenAPI document and a validator for its schemas."""

    def __init__(self, path):
        with open(path, encoding="utf-8") as f:
            self.doc = yaml.safe_load(f)
        jsonschema.Draft202012Validator.check_schema(
            {"$defs": self.doc["components"]["schemas"]})
        self.resolver = jsonschema.RefResolver.from_schema(self.doc)
        self.templates = []
        for template, item in self.doc["paths"].items():
            regex = "^" + re.sub(r"\\\{[^}]+\\\}", "[^/]+",
                                 re.escape(template)) + "$"
            for method in item:
                if method in ("get", "post", "put", "delete", "patch"):
                    self.templates.append((template, method.upper(),
                                           re.compile(regex)))
        # Literal templates win over parameterised ones (/v1/models/active
        # over /v1/models/{version}).
        self.templates.sort(key=lambda t: t[0].count("{"))

    def operation(self, method, path):
        path = path.split("?", 1)[0]
        for template, m, regex in self.templates:
            if m == method and regex.match(path):
                return template, self.doc["paths"][template][method.lower()]
        return None, None

    def resolve(self, node):
        while isinstance(node, dict) and "$ref" in node:
            _, node = self.resolver.resolve(node["$ref"])
        return node

    def check(self, method, path, status, content_type, body):
        """Returns the operation's template; raises AssertionError."""
        template, op = self.operation(method, path)
        if op is None:
            raise AssertionError(f"{method} {path}: not in the OpenAPI file")
        responses = op["responses"]
        key = str(status)
        if key not in responses:
            raise AssertionError(
                f"{method} {path} answered {status}, which {template} does "
                f"not list ({sorted(responses)})")
        response = self.resolve(responses[key])
        content = response.get("content", {})
        media = content_type.split(";")[0].strip()
        if media not in content:
            raise AssertionError(
                f"{method} {path} {status}: content type {media!r}, the file "
                f"lists {sorted(content)}")
        schema = content[media].get("schema")
        if schema is not None and media == "application/json":
            instance = json.loads(body)
            validator = jsonschema.Draft202012Validator(
                schema, resolver=self.resolver)
            errors = sorted(validator.iter_errors(instance),
                            key=lambda e: list(e.absolute_path))
            if errors:
                e = errors[0]
                where = "/".join(str(p) for p in e.absolute_path)
                raise AssertionError(
                    f"{method} {path} {status}: body does not match "
                    f"{template}'s schema at '{where}': {e.message}")
        return template


class Client:
    def __init__(self, base):
        self.base = base

    def call(self, method, path, body=None, token=True, raw=None):
        data = None
        if raw is not None:
            data = raw
        elif body is not None:
            data = json.dumps(body).encode()
        req = urllib.request.Request(self.base + path, data=data,
                                     method=method)
        if data is not None:
            req.add_header("Content-Type", "application/json")
        if token:
            req.add_header("Authorization", "Bearer " + TOKEN)
        try:
            with urllib.request.urlopen(req, timeout=30) as r:
                return r.status, r.headers.get("Content-Type", ""), r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type", ""), e.read()


def start_daemon(rollwear, db, log_path, env):
    log = open(log_path, "w", encoding="utf-8")
    proc = subprocess.Popen(
        [rollwear, "serve", "--db", db, "--port", "0", "--bind", "127.0.0.1"],
        stdout=log, stderr=subprocess.STDOUT, env=env)
    marker = "rollwear: listening on http://127.0.0.1:"
    deadline = time.time() + 60
    while time.time() < deadline:
        text = open(log_path, encoding="utf-8", errors="replace").read()
        i = text.find(marker)
        if i >= 0:
            m = re.match(r"(\d+)", text[i + len(marker):])
            if m:
                return proc, int(m.group(1))
        if proc.poll() is not None:
            break
        time.sleep(0.05)
    proc.kill()
    raise RuntimeError("daemon did not start:\n" + open(log_path).read())


def daemon_routes(table):
    """(method, path) of every route declared in the route table
    (api/router_routes.cc: rows `{{RouteId::k..., "METHOD", "/pattern", ...`);
    a "{name*}" parameter is the OpenAPI "{name}"."""
    routes = []
    with open(table, encoding="utf-8") as f:
        for line in f:
            m = re.search(r'\{\{RouteId::k\w+,\s*"(GET|POST|PUT|DELETE)",\s*'
                          r'"(/[^"]*)"', line)
            if m:
                routes.append((m.group(1), m.group(2).replace("*}", "}")))
    if len(routes) < 10:
        raise RuntimeError(f"{table}: found only {len(routes)} routes")
    return routes


def wait_done(client, path, seconds=300):
    deadline = time.time() + seconds
    while time.time() < deadline:
        status, _, body = client.call("GET", path)
        if status == 200 and json.loads(body)["status"] in ("done", "failed"):
            return json.loads(body)
        time.sleep(0.2)
    raise AssertionError(f"{path} not done within {seconds} s")


def exercise(client, data_dir):
    """Yields (method, path, expected status, request kwargs) and answers."""
    calls = []

    def call(method, path, expect, **kw):
        status, ctype, body = client.call(method, path, **kw)
        if status != expect:
            raise AssertionError(f"{method} {path}: expected {expect}, got "
                                 f"{status}: {body[:300]!r}")
        calls.append((method, path, status, ctype, body))
        return json.loads(body) if "json" in ctype else body

    wear = call("GET", "/v1/wear", 200)
    first = wear["positions"][0]
    stand, position = first["stand"], first["position"]
    call("GET", f"/v1/wear/{stand}/{position}", 200)
    call("GET", "/v1/wear/F1/top", 404)
    campaign = first["campaign_id"]

    # A new campaign, a coil, its end and a measurement, with repeats.
    rolls = [{"stand": p["stand"], "position": p["position"],
              "roll_id": "OA-" + p["stand"] + p["position"],
              "roll_type": p["roll_type"], "diameter_mm": 700.0,
              "hardness_hb": 550} for p in wear["positions"]]
    change = {"campaign_id": "OA1", "started_at": "2031-01-01T00:00:00Z",
              "rolls": rolls}
    call("POST", "/v1/roll-changes", 201, body=change)
    call("POST", "/v1/roll-changes", 200, body=change)
    call("POST", "/v1/roll-changes", 401, body=change, token=False)
    other = dict(change, started_at="2031-01-01T00:00:01Z")
    call("POST", "/v1/roll-changes", 409, body=other)
    stands = sorted({r["stand"] for r in rolls})
    coil = {"coil_id": "OA-K1", "campaign_id": "OA1", "seq": 1,
            "rolled_at": "2031-01-01T00:10:00Z", "grade": "S355",
            "passes": [{"stand": s, "force_kn": 18000, "width_mm": 1250,
                        "length_m": 900, "entry_thickness_mm": 4.0,
                        "exit_thickness_mm": 3.3, "temperature_c": 900,
                        "speed_mps": 10, "lubrication": 1, "shift_mm": 0}
                       for s in stands]}
    call("POST", "/v1/coils", 201, body=coil)
    call("POST", "/v1/coils", 200, body=coil)
    call("POST", "/v1/coils", 400, raw=b"{")
    bad = json.loads(json.dumps(coil))
    bad["passes"][0]["force_kn"] = -3
    call("POST", "/v1/coils", 400, body=dict(bad, coil_id="OA-K2"))
    call("POST", "/v1/coils", 404, body=dict(coil, coil_id="OA-K3",
                                              campaign_id="nope"))
    f1 = json.loads(json.dumps(coil))
    f1["passes"][0]["stand"] = "F1"
    call("POST", "/v1/coils", 422, body=dict(f1, coil_id="OA-K4", seq=2))
    call("POST", "/v1/coils", 413,
         raw=b'{"pad":"' + b"x" * (2 << 20) + b'"}')
    # Limits and a forecast while OA1 runs.
    call("GET", f"/v1/wear/{stand}/{position}/profile", 200)
    call("GET", "/v1/wear/F1/top/profile", 404)
    call("GET", "/v1/limits", 200)
    call("POST", f"/v1/limits/{stand}/{position}", 200,
         body={"limit_um": 300, "reason": "openapi test"})
    call("POST", f"/v1/limits/{stand}/{position}", 400, body={"limit_um": -1})
    call("POST", f"/v1/limits/{stand}/{position}", 401,
         body={"limit_um": 300}, token=False)
    call("POST", "/v1/limits/F9/top", 404, body={"limit_um": 300})
    call("GET", "/v1/wear", 200)
    planned = [dict(coil, coil_id=f"OA-P{i}", seq=10 + i) for i in range(5)]
    call("POST", "/v1/forecast", 200, body={"coils": planned})
    call("POST", "/v1/forecast", 400, body={"coils": []})
    call("POST", "/v1/forecast", 422, body={"coils": [f1]})
    call("POST", "/v1/campaigns/OA1/end", 200,
         body={"ended_at": "2031-01-02T00:00:00Z"})
    call("POST", "/v1/campaigns/nope/end", 404,
         body={"ended_at": "2031-01-02T00:00:00Z"})
    call("POST", "/v1/coils", 422, body=dict(coil, coil_id="OA-K5", seq=3))
    meas = {"campaign_id": "OA1", "stand": rolls[0]["stand"],
            "position": rolls[0]["position"], "roll_id": rolls[0]["roll_id"],
            "measured_at": "2031-01-02T06:00:00Z", "wear_center_um": 12.5}
    call("POST", "/v1/measurements", 201, body=meas)
    call("POST", "/v1/measurements", 200, body=meas)
    call("POST", "/v1/measurements", 409, body=dict(meas, wear_center_um=13))
    call("POST", "/v1/measurements", 422,
         body=dict(meas, stand=rolls[1]["stand"],
                   position=rolls[1]["position"], roll_id="other"))
    profile = {k: meas[k] for k in ("campaign_id", "stand", "position",
                                     "roll_id", "measured_at")}
    profile["points"] = [{"x_mm": x, "wear_um": 12.5 + abs(x) / 100}
                         for x in (-500, -250, 0, 250, 500)]
    call("POST", "/v1/profiles", 201, body=profile)
    call("POST", "/v1/profiles", 200, body=profile)
    call("POST", "/v1/profiles", 401, body=profile, token=False)
    call("POST", "/v1/profiles", 409,
         body=dict(profile, points=profile["points"][:4]))
    call("POST", "/v1/profiles", 400,
         body=dict(profile, points=[{"x_mm": 1500, "wear_um": 1}]))
    call("POST", "/v1/profiles", 404, body=dict(profile, campaign_id="nope"))
    call("POST", "/v1/profiles", 422,
         body=dict(profile, stand=rolls[1]["stand"],
                   position=rolls[1]["position"], roll_id="other"))

    # Calibrations, models, diagnoses.
    queued = call("POST", "/v1/calibrations", 202, body={})
    call("POST", "/v1/calibrations", 400, body={"modle": "cao"})
    wait_done(client, f"/v1/calibrations/{queued['id']}")
    call("GET", f"/v1/calibrations/{queued['id']}", 200)
    call("GET", "/v1/calibrations/999999", 404)
    call("GET", "/v1/calibrations?limit=5", 200)
    call("GET", "/v1/models/active", 200)
    models = call("GET", "/v1/models", 200)["models"]
    if not models:
        raise AssertionError("no model version was promoted: the test needs "
                             "one to exercise /v1/models/{version}")
    version = models[-1]["version"]
    call("GET", f"/v1/models/{version}", 200)
    call("GET", "/v1/models/999999", 404)
    call("POST", f"/v1/models/{version}/activate", 200,
         body={"reason": "openapi test"})
    call("POST", f"/v1/models/{version}/activate", 400, body={})
    call("POST", f"/v1/models/{version}/activate", 401,
         body={"reason": "x"}, token=False)
    call("POST", "/v1/models/999999/activate", 404, body={"reason": "x"})
    call("POST", f"/v1/models/{version}/activate", 200,
         body={"reason": "openapi test: unpin", "pin": False})
    call("GET", "/v1/models/history", 200)
    rolls = call("GET", "/v1/rolls", 200)["rolls"]
    roll_id = rolls[0]["roll_id"]
    call("GET", f"/v1/rolls/{roll_id}", 200)
    call("GET", "/v1/rolls/no-such-roll", 404)
    call("GET", f"/rolls/{roll_id}", 200)
    call("GET", "/rolls/no-such-roll", 404)
    dq = call("POST", "/v1/diagnoses", 202, body={})
    call("POST", "/v1/diagnoses", 400, body={"adopt": "yes"})
    wait_done(client, f"/v1/diagnoses/{dq['id']}", 600)
    call("GET", f"/v1/diagnoses/{dq['id']}", 200)
    call("GET", "/v1/diagnoses", 200)
    call("GET", f"/v1/diagnoses/{dq['id']}/report", 200)
    call("GET", "/v1/diagnoses/999999/report", 404)
    call("GET", "/v1/diagnoses/999999", 404)

    call("GET", "/healthz", 200)
    call("GET", "/metrics", 200)
    call("GET", "/", 200)
    return calls


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rollwear", required=True)
    ap.add_argument("--spec", required=True)
    ap.add_argument("--routes", required=True)
    args = ap.parse_args()

    spec = Spec(args.spec)
    work = tempfile.mkdtemp(prefix="rollwear-openapi-")
    proc = None
    try:
        data = os.path.join(work, "data")
        subprocess.run([args.rollwear, "simulate", "--out", data, "--seed",
                        "5", "--campaigns", "30", "--coils-per-campaign",
                        "25"], check=True, stdout=subprocess.DEVNULL)
        env = dict(os.environ, ROLLWEAR_TOKEN=TOKEN)
        proc, port = start_daemon(args.rollwear, os.path.join(work, "db"),
                                  os.path.join(work, "serve.log"), env)
        base = f"http://127.0.0.1:{port}"
        subprocess.run([args.rollwear, "replay", "--data", data, "--url",
                        base, "--token", TOKEN, "--quiet",
                        "--leave-last-open"], check=True)
        calls = exercise(Client(base), data)

        failures = []
        answered = set()
        for method, path, status, ctype, body in calls:
            try:
                template = spec.check(method, path, status, ctype, body)
                if 200 <= status < 300:
                    answered.add((method, template))
            except AssertionError as e:
                failures.append(str(e))
        listed = {(m, t) for t, m, _ in spec.templates}
        for method, route in daemon_routes(args.routes):
            if (method, route) not in listed:
                failures.append(f"{method} {route}: served by the daemon "
                                f"({args.routes}) but not in the OpenAPI file")
        for template, method, _ in spec.templates:
            if (method, template) not in answered:
                failures.append(f"{method} {template}: in the OpenAPI file "
                                "but never answered 2xx by this test")
        print(f"openapi_test: {len(calls)} answers checked against "
              f"{len(spec.templates)} operations; {len(failures)} failures")
        for f in failures:
            print("  FAIL " + f)
        return 1 if failures else 0
    finally:
        if proc is not None:
            proc.terminate()
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
