"""`import leafdig` through its real interface, against the CLI's own outputs (issue 30).

Run by ctest (test `Python.pytest`) with PYTHONPATH at the build's python/ folder and
LEAFDIG_CLI, LEAFDIG_SOURCE_DIR set; by hand:
    PYTHONPATH=build/ci/python LEAFDIG_CLI=build/ci/ui/cli/leafdig /usr/bin/python3 -m pytest tests/python
"""
import hashlib
import json
import os
import sqlite3
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import leafdig

SOURCE = Path(os.environ.get("LEAFDIG_SOURCE_DIR", Path(__file__).resolve().parents[2])).resolve()
CLI = os.path.abspath(os.environ.get("LEAFDIG_CLI", str(SOURCE / "build/ci/ui/cli/leafdig")))
SAMPLES = sorted((SOURCE / "data/samples").glob("*.markers.json"))
PLAN = SOURCE / "data/plants/tobacco-p07.plant.json"


def cli(*args, check=True):
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError("leafdig %s: exit %d: %s" % (" ".join(map(str, args)), r.returncode, r.stderr))
    return r


def cli_json(*args):
    return json.loads(cli(*args, "--json").stdout)


def test_the_version_is_the_commands():
    assert cli("--version").stdout.strip().endswith(leafdig.__version__)


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_a_leaf_is_the_one_model_build_makes(path):
    leaf = leafdig.build_leaf(path)
    built = cli_json("model", "build", path)
    assert leaf.metrics == built["metrics"]  # every number, exactly
    mesh = leaf.mesh()
    assert len(mesh.faces) == built["mesh"]["triangles"]
    assert mesh.organ_names == [o["name"] for o in built["mesh"]["organs"]]
    counts = np.bincount(mesh.organs, minlength=len(mesh.organ_names))
    assert counts.tolist() == [o["triangles"] for o in built["mesh"]["organs"]]
    assert mesh.vertices.shape == (len(mesh.normals), 3) and mesh.vertices.dtype == np.float64
    assert mesh.faces.max() < len(mesh.vertices)
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0)


def test_build_options_are_model_builds():
    path = SAMPLES[0]
    leaf = leafdig.build_leaf(path, blade="approx", mesh="adaptive", max_error=0.2, frame="leaf")
    built = cli_json("model", "build", path, "--blade", "approx", "--mesh", "adaptive", "--max-error", "0.2",
                     "--frame", "leaf", "--no-measure")
    assert leaf.metrics == built["metrics"]
    assert len(leaf.mesh().faces) == built["mesh"]["triangles"]
    with pytest.raises(leafdig.InputError, match="adaptive"):
        leafdig.build_leaf(path, max_error=0.2)
    with pytest.raises(leafdig.InputError, match="frame"):
        leafdig.build_leaf(path, frame="world")


def test_markers_are_arrays_in_mm(tmp_path):
    path = SAMPLES[0]
    doc = json.loads(path.read_text())
    m = leafdig.read_markers(path)
    assert m.rows.shape == (len(doc["rows"]), 7, 3)
    assert np.allclose(m.tip, doc["tip"])
    assert np.allclose(m.rows[0], doc["rows"][0]["points"])
    assert m.midrib_thickness.shape == (len(doc["rows"]),)
    lateral, midrib, tip, mode = m.rule_thickness()
    assert lateral.shape == (len(doc["rows"]), 7) and np.all(lateral > 0) and np.all(midrib > 0)
    assert json.loads(m.to_json())["rows"][0]["points"] == doc["rows"][0]["points"]


def test_the_model_evaluates_its_veins_and_blade():
    leaf = leafdig.build_leaf(SAMPLES[0])
    model = leaf.model
    assert [v["name"] for v in model["veins"]] == leaf.vein_names
    midrib = leaf.vein("midrib", np.linspace(0, 1, 5))
    assert midrib.shape == (5, 4) and np.all(midrib[:, 3] > 0)
    # The midrib runs from the tip to the base marker.
    assert np.linalg.norm(midrib[0, :3] - leaf.markers.tip) < 1e-6
    assert np.linalg.norm(midrib[-1, :3] - leaf.markers.rows[-1, 3]) < 1e-6
    corners = leaf.blade([0, 1], [0.5, 0.5])
    assert corners.shape == (2, 3)
    with pytest.raises(leafdig.InputError):
        leaf.vein(0, [1.5])


def test_exports_are_the_commands_files(tmp_path):
    path = SAMPLES[1]
    leaf = leafdig.build_leaf(path)
    for ext in ("glb", "obj", "ply", "stl", "mtg", "csv"):
        mine, theirs = tmp_path / ("py." + ext), tmp_path / ("cli." + ext)
        assert str(mine) in leaf.export(mine)
        cli("model", "build", path, "-o", theirs)
        assert mine.read_bytes() == theirs.read_bytes(), ext
    assert any(p.endswith(".opt") for p in leaf.export(tmp_path / "py.can"))
    doc = json.loads(Path(leaf.export(tmp_path / "model.json")[0]).read_text())
    assert doc["metrics"]["blade_area_mm2"] == pytest.approx(leaf.metrics["blade_area_mm2"], rel=1e-12)
    with pytest.raises(OSError):
        leaf.export(tmp_path / "no" / "such" / "dir" / "x.glb")


def test_bad_input_raises_input_error_naming_the_row(tmp_path):
    doc = json.loads(SAMPLES[0].read_text())
    doc["rows"][2]["points"] = doc["rows"][2]["points"][:6]
    bad = tmp_path / "bad.markers.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(leafdig.InputError, match="row 3") as e:
        leafdig.read_markers(bad)
    assert isinstance(e.value, ValueError)
    assert cli("model", "build", bad, check=False).returncode == 2
    with pytest.raises(OSError):
        leafdig.read_markers(tmp_path / "missing.markers.json")


def test_a_synthetic_leaf_comes_with_its_truth():
    markers, truth = leafdig.synth_leaf(shape="obovate", rows=14, noise=0.1, seed=5)
    assert markers.rows.shape == (14, 7, 3)
    area = leafdig.build_leaf(markers).metrics["blade_area_mm2"]
    assert area == pytest.approx(truth["area_mm2"], rel=0.03)
    again, _ = leafdig.synth_leaf(shape="obovate", rows=14, noise=0.1, seed=5)
    assert np.array_equal(again.rows, markers.rows)
    with pytest.raises(leafdig.InputError):
        leafdig.synth_leaf(shape="heart")


@pytest.fixture(scope="module")
def station(tmp_path_factory):
    """A station file written by a simulated capture (the real drivers on pseudo-terminals)."""
    db = tmp_path_factory.mktemp("station") / "station.sqlite"
    cli("capture", "--simulate", "--speed", "20", "--no-mistakes", "--db", db, "--markers", SAMPLES[0],
        "--station", "bench-py")
    cli("plant", "capture", "--simulate", "--speed", "20", "--db", db, "--station", "bench-py")
    return db


def test_a_station_files_sessions_are_listed_and_built_as_the_station_does(station, tmp_path):
    store = leafdig.open(station)
    sessions = store.sessions()
    assert [s["kind"] for s in sessions] == ["leaf", "plant"]
    assert store.sessions(kind="leaf", status="complete")[0]["id"] == 1
    listed = cli_json("sessions", "list", "--db", station)
    assert [s["id"] for s in sessions] == [s["id"] for s in listed]
    # The markers and the model are the exported session's.
    cli("sessions", "export", 1, "--db", station, "--out", tmp_path, "--format", "markers")
    exported = leafdig.read_markers(tmp_path / "session-1.markers.json")
    assert np.array_equal(store.markers(1).rows, exported.rows)
    assert store.leaf(1).metrics == cli_json("model", "build", tmp_path / "session-1.markers.json")["metrics"]
    events = store.events(1)
    assert events[0]["seq"] == 1 and events[-1]["kind"] == "status"
    assert isinstance(events[1]["payload"], dict)
    survey = store.plant_survey(2)
    assert len(survey["nodes"]) == 5
    with pytest.raises(leafdig.InputError, match="filter"):
        store.sessions(colour="green")
    # A word no session holds is refused with the words there are, not an empty list.
    with pytest.raises(leafdig.InputError, match="kind is one of leaf, plant"):
        store.sessions(kind="leaves")
    with pytest.raises(leafdig.InputError, match="status is one of open, complete"):
        store.sessions(status="done")
    assert store.sessions(kind="plant")[0]["id"] == 2


def test_a_captured_plant_is_the_model_its_session_export_writes(station, tmp_path):
    plant = leafdig.open(station).plant(2)
    cli("sessions", "export", 2, "--db", station, "--out", tmp_path, "--format", "model,can")
    model = json.loads((tmp_path / "session-2.plant-model.json").read_text())
    assert plant.metrics["area_mm2"] == pytest.approx(model["metrics"]["area_mm2"], rel=1e-12)
    lines = [l for l in (tmp_path / "session-2.can").read_text().splitlines() if l.startswith("p ")]
    assert sum(len(t) for t in plant.caribu_scene().values()) == len(lines)
    # One MTG for a captured plant (issue 51: Python gave the plan's, the export the survey's):
    # the survey's, byte for byte what `sessions export` writes, and its CSV likewise.
    cli("sessions", "export", 2, "--db", station, "--out", tmp_path, "--format", "mtg,csv")
    assert plant.mtg() == (tmp_path / "session-2.mtg").read_text()
    assert plant.csv() == (tmp_path / "session-2.plant.csv").read_text()
    assert "\n/P1/I0\t" in plant.mtg()
    with pytest.raises(leafdig.StoreError, match="one leaf"):
        leafdig.open(station).plant(1)
    # A full leaf of the captured plant is a Leaf like a leaf session's: the markers
    # `sessions export --node` writes, built the same.
    store = leafdig.open(station)
    full = next(l["node"] for l in cli_json("sessions", "show", 2, "--db", station)["leaves"] if l["kind"] == "full")
    cli("sessions", "export", 2, "--db", station, "--out", tmp_path, "--node", full, "--format", "markers")
    exported = leafdig.read_markers(tmp_path / ("session-2.node-%d.markers.json" % full))
    assert np.array_equal(store.markers(2, node=full).rows, exported.rows)
    assert store.leaf(2, node=full).metrics == cli_json("model", "build", tmp_path / (
        "session-2.node-%d.markers.json" % full))["metrics"]
    quick = next(l["node"] for l in cli_json("sessions", "show", 2, "--db", station)["leaves"] if l["kind"] != "full")
    with pytest.raises(leafdig.InputError, match="its full leaves are at node %d" % full):
        store.leaf(2, node=quick)
    with pytest.raises(leafdig.InputError, match="node is a plant's node number"):
        store.leaf(2, node=0)


def test_a_doctored_station_file_is_not_trusted(station, tmp_path):
    doctored = tmp_path / "doctored.sqlite"
    doctored.write_bytes(station.read_bytes())
    with sqlite3.connect(doctored) as c:
        # As an attacker with sqlite3 would: the append-only trigger dropped, a payload edited,
        # the trigger put back as it was.
        (trigger,) = c.execute("SELECT sql FROM sqlite_master WHERE name = 'events_no_update'").fetchone()
        c.execute("DROP TRIGGER events_no_update")
        c.execute("UPDATE events SET payload_json = replace(payload_json, '.', ',') WHERE session_id = 1 AND seq = 5")
        c.execute(trigger)
    dropped = tmp_path / "dropped.sqlite"
    dropped.write_bytes(station.read_bytes())
    with sqlite3.connect(dropped) as c:
        c.execute("DROP TRIGGER events_no_update")
    with pytest.raises(leafdig.StoreError, match="events_no_update"):
        leafdig.open(dropped)
    store = leafdig.open(doctored)
    with pytest.raises(leafdig.StoreError, match="verify"):
        store.events(1)
    with pytest.raises(leafdig.StoreError, match="verify"):
        store.markers(1)
    with pytest.raises(leafdig.StoreError):
        leafdig.open(tmp_path / "none.sqlite")


def test_a_read_only_store_decides_nothing_and_a_writable_one_approves(station, tmp_path):
    copy = tmp_path / "copy.sqlite"
    copy.write_bytes(station.read_bytes())
    with pytest.raises(leafdig.StoreError):
        leafdig.open(copy).approve(1, who="kim")
    writable = leafdig.open(copy, writable=True)
    with pytest.raises(leafdig.InputError, match="why"):
        writable.reject(1, who="kim", why="")
    writable.approve(1, who="kim")
    assert writable.sessions(id=1)[0]["status"] == "approved"
    assert cli_json("sessions", "list", "--db", copy)[0]["status"] == "approved"


def test_a_plant_is_the_one_plant_build_makes(tmp_path, monkeypatch):
    plant = leafdig.build_plant(PLAN)
    built = cli_json("plant", "build", PLAN, "-o", tmp_path / "p.glb", "--no-measure")["states"][0]
    assert plant.metrics == built["metrics"]
    assert [l["area_mm2"] for l in plant.leaves] == [l["area_mm2"] for l in built["leaves"]]
    assert len(plant.mesh().faces) == built["triangles"]
    cli("plant", "build", PLAN, "-o", tmp_path / "p.mtg", "-o", tmp_path / "p.can")
    assert plant.mtg() == (tmp_path / "p.mtg").read_text()
    # CARIBU's scene: every triangle of the .can, under the .can's labels.
    scene = plant.caribu_scene()
    lines = [l.split() for l in (tmp_path / "p.can").read_text().splitlines() if l.startswith("p ")]
    assert sum(len(t) for t in scene.values()) == len(lines)
    assert set(scene) == {int(l[2]) for l in lines}
    first = lines[0]
    assert scene[int(first[2])][0] == [tuple(float(x) for x in first[4 + 3 * k:7 + 3 * k]) for k in range(3)]
    # As CARIBU's CaribuScene checks a dict scene (issue 51: tuples of tuples were refused with
    # "Unrecognised scene format"): every value a list of triangles, each triangle a list of
    # three 3-tuples of numbers.
    for label, triangles in scene.items():
        assert isinstance(label, int) and isinstance(triangles, list)
        for t in triangles:
            assert isinstance(t, list) and len(t) == 3
            assert all(isinstance(p, tuple) and len(p) == 3 and all(isinstance(c, float) for c in p) for p in t)
    written = plant.export(tmp_path / "q.glb")
    assert Path(written[0]).stat().st_size > 1000
    with open(PLAN) as f:
        as_dict = json.load(f)
    monkeypatch.chdir(PLAN.parent)  # a dict's relative paths are the working directory's
    assert leafdig.build_plant(as_dict).metrics == plant.metrics


def test_an_archived_plant_is_the_one_plant_import_makes(tmp_path):
    # Issue 51: OpenAlea's apple tree (tests/data/archives, CeCILL-C) through Python as through
    # the command: the same report, the same MTG and CSV, and every format written.
    archives = SOURCE / "tests/data/archives"
    tree = leafdig.import_plant(archives / "agraf.mtg", "mm", drf=archives / "agraf.drf", resolution="preview")
    made = cli_json("plant", "import", archives / "agraf.mtg", "--drf", archives / "agraf.drf", "--units", "mm",
                    "--resolution", "preview", "-o", tmp_path / "a.mtg", "-o", tmp_path / "a.csv")
    report = tree.report
    assert report["vertices"] == made["vertices"] and report["points"] == made["points"]
    assert report["classes"] == made["classes"]
    assert {str(k): v for k, v in report["axes_by_order"].items()} == made["axes_by_order"]
    assert tree.mtg() == (tmp_path / "a.mtg").read_text()
    assert tree.csv() == (tmp_path / "a.csv").read_text()
    assert tree.id == "P1" and tree.leaves == []
    for ext in ("glb", "xml", "vgx"):
        assert Path(tree.export(tmp_path / ("b." + ext))[0]).stat().st_size > 1000
    assert leafdig.build_plant(PLAN).report == {}
    with pytest.raises(leafdig.InputError, match="give mm, cm or m"):
        leafdig.import_plant(archives / "agraf.mtg", "inches")


def test_a_hydroshoot_table_imports_in_centimetres_without_being_told(tmp_path):
    # Issue 51: HydroShoot's grapevine digitizing table (tests/data/archives, CeCILL-C): no unit
    # given (the table's own, cm), the same report and CSV as the command's; an MTG still needs one.
    table = SOURCE / "tests/data/archives/grapevine_gdc_can1.digit.input"
    vine = leafdig.import_plant(table, resolution="preview")
    made = cli_json("plant", "import", table, "--resolution", "preview", "-o", tmp_path / "v.csv")
    assert vine.report["units"] == "cm" == made["units"]
    assert vine.report["classes"] == made["classes"] and vine.report["points"] == made["points"]
    assert vine.csv() == (tmp_path / "v.csv").read_text()
    assert vine.id == "plant1"
    with pytest.raises(leafdig.InputError, match="does not say the unit"):
        leafdig.import_plant(SOURCE / "tests/data/archives/agraf.mtg")


def test_to_openalea_hands_the_plants_mtg_to_openaleas_reader(monkeypatch):
    # Issue 51: Plant.to_openalea() when OpenAlea is importable. OpenAlea is not a Debian
    # package: a stand-in module records what leafdig hands its reader, and without one the
    # error says what to do.
    import sys
    import types
    plant = leafdig.build_plant(PLAN, resolution="preview")
    monkeypatch.setitem(sys.modules, "openalea", None)
    with pytest.raises(ImportError, match="needs OpenAlea's MTG package"):
        plant.to_openalea()
    given = []
    io = types.SimpleNamespace(read_mtg=lambda text: given.append(text) or "an MTG")
    package = types.ModuleType("openalea")
    mtg = types.ModuleType("openalea.mtg")
    mtg.io = io
    package.mtg = mtg
    monkeypatch.setitem(sys.modules, "openalea", package)
    monkeypatch.setitem(sys.modules, "openalea.mtg", mtg)
    assert plant.to_openalea() == "an MTG"
    assert given == [plant.mtg()]


def test_a_plant_grows():
    plants = leafdig.grow(PLAN, [10, 30, 60])
    areas = [p.metrics["area_mm2"] for p in plants]
    assert areas == sorted(areas) and areas[0] < areas[-1]
    assert [p.time for p in plants] == [10, 30, 60]
    with pytest.raises(leafdig.InputError):
        leafdig.build_plant({"format": "leafdig.plant/1"})


def test_heavy_calls_let_other_python_threads_run():
    """While a thread is inside build_leaf, the main thread keeps running Python: the call
    released the GIL. (No timing is asserted: only that some of the main thread's steps fall
    strictly inside a call.)"""
    calls, ticks, done = [], [], threading.Event()

    def builder():
        for _ in range(3):
            start = time.perf_counter()
            leafdig.build_leaf(SAMPLES[2], resolution="reference")
            calls.append((start, time.perf_counter()))
        done.set()

    t = threading.Thread(target=builder)
    t.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
    t.join()
    # The middle half of each call: away from the moments the interpreter may switch threads
    # around entering and leaving it.
    inside = sum(1 for a, b in calls for x in ticks if a + (b - a) / 4 < x < b - (b - a) / 4)
    assert inside > 0


def test_the_python_walk_through_runs_as_written(tmp_path):
    """docs/python.md's Python blocks, in order, in one namespace, against a fresh demo (its
    shell line run as written). With LEAFDIG_UPDATE_DOCS=1 the figure is copied to docs/."""
    doc = (SOURCE / "docs/python.md").read_text()
    blocks = [b.split("```", 1)[0] for b in doc.split("```python\n")[1:]]
    assert len(blocks) >= 4
    assert "leafdig demo --out out/demo --speed 20 --synth-leaves 0" in doc
    cli("demo", "--out", tmp_path / "out/demo", "--speed", "20", "--synth-leaves", "0",
        "--samples", SOURCE / "data/samples")
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        namespace = {}
        for block in blocks:
            exec(compile(block, "docs/python.md", "exec"), namespace)
    finally:
        os.chdir(here)
    assert (tmp_path / "thickness.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert namespace["plant"].metrics["area_mm2"] > 0
    assert sum(len(t) for t in namespace["scene"].values()) == len(namespace["plant"].mesh().faces)
    assert "\nCODE:" in namespace["mtg"]
    if os.environ.get("LEAFDIG_UPDATE_DOCS") == "1":
        (SOURCE / "docs/python-thickness.png").write_bytes((tmp_path / "thickness.png").read_bytes())


@pytest.fixture(scope="module")
def lab(tmp_path_factory, station):
    """A throw-away PostgreSQL server (Debian's binaries; as the postgres user when root, as
    tests/support/pg_cluster.hpp does) with leafdig's schema, a technician of bench-py, a
    curator and a reader; the station file pushed by its technician."""
    import pwd
    import shutil
    import socket
    import tempfile
    bindir = subprocess.run(["pg_config", "--bindir"], capture_output=True, text=True).stdout.strip()
    if not bindir or not Path(bindir, "initdb").exists():
        bindir = "/usr/lib/postgresql/15/bin"
    home = Path(tempfile.mkdtemp(prefix="leafdig-pg-py-"))
    as_user = []
    if os.geteuid() == 0:
        pw = pwd.getpwnam("postgres")
        os.chown(home, pw.pw_uid, pw.pw_gid)
        as_user = ["runuser", "-u", "postgres", "--"]
    password = "adm-pass-%d" % os.getpid()
    (home / "pw").write_text(password + "\n")
    if as_user:
        os.chown(home / "pw", pw.pw_uid, pw.pw_gid)

    def run(*argv):
        r = subprocess.run(as_user + list(argv), capture_output=True, text=True)
        assert r.returncode == 0, "%s: %s%s" % (argv[0], r.stdout, r.stderr)

    run(bindir + "/initdb", "-D", str(home / "data"), "-U", "leafdig_admin", "--pwfile", str(home / "pw"),
        "--auth-local=trust", "--auth-host=scram-sha-256", "-E", "UTF8", "--locale=C", "--no-sync")
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    run(bindir + "/pg_ctl", "-D", str(home / "data"), "-l", str(home / "log"), "-w", "-t", "60", "-o",
        "-p %d -k %s -c listen_addresses=127.0.0.1 -c fsync=off" % (port, home), "start")
    try:
        run(bindir + "/psql", "-h", str(home), "-p", str(port), "-U", "leafdig_admin", "-d", "postgres", "-c",
            "CREATE DATABASE lab ENCODING 'UTF8' TEMPLATE template0")
        url = lambda login, pw: "postgresql://%s:%s@127.0.0.1:%d/lab" % (login, pw, port)  # noqa: E731
        admin = url("leafdig_admin", password)
        cli("server", "init", "--url", admin)
        logins = {}
        for login, role, extra in (("tech_py", "technician", ["--station", "bench-py"]), ("carla_py", "curator", []),
                                   ("rita_py", "reader", [])):
            pwfile = home / (login + ".pw")
            pwfile.write_text("s3cret-" + login + "\n")
            cli("server", "add-user", "--url", admin, "--login", login, "--role", role, "--password-file", pwfile, *extra)
            logins[role] = url(login, "s3cret-" + login)
        cli("sync", "push", "--db", station, "--to", logins["technician"])
        yield logins
    finally:
        subprocess.run(as_user + [bindir + "/pg_ctl", "-D", str(home / "data"), "-m", "immediate", "-w", "stop"],
                       capture_output=True)
        shutil.rmtree(home, ignore_errors=True)


def test_a_curator_corrects_a_leaf_and_a_plant_from_python(station, tmp_path):
    copy = tmp_path / "copy.sqlite"
    copy.write_bytes(station.read_bytes())
    before = leafdig.open(copy).markers(1).rows
    moved = before[1][2] + np.array([0.5, -0.25, 0.0])
    with pytest.raises(leafdig.StoreError):  # read only unless asked
        leafdig.open(copy).correct(1, "marker", row=2, col=3, position=moved, who="kim", why="slipped")
    store = leafdig.open(copy, writable=True)
    events = len(store.events(1))
    for what, kwargs, words in (("lasers", {"value": 1.0}, "is not an item"),
                                ("marker", {"row": 2, "col": 3, "position": moved, "why": ""}, "reason"),
                                ("marker", {"row": 2, "col": 3, "position": (1.0, 2.0)}, "position"),
                                ("midrib_thickness", {"row": 2, "col": 4, "value": 1e9}, "range")):
        kwargs.setdefault("why", "slipped")
        with pytest.raises(leafdig.InputError, match=words):
            store.correct(1, what, who="kim", **kwargs)
    assert len(store.events(1)) == events  # nothing written
    seq = store.correct(1, "marker", row=2, col=3, position=moved, who="kim", why="the stylus slipped")
    assert seq == events + 1 and store.events(1)[-1]["kind"] == "corrected"
    after = store.markers(1).rows
    changed = np.argwhere(np.any(after != before, axis=2))
    assert changed.tolist() == [[1, 2]] and np.array_equal(after[1][2], moved)
    assert store.events(1)[-1]["payload"]["who"] == "kim"
    # The CLI exports the same corrected markers, and the corrected leaf builds to its numbers.
    cli("sessions", "export", 1, "--db", copy, "--out", tmp_path, "--format", "markers")
    assert np.array_equal(leafdig.read_markers(tmp_path / "session-1.markers.json").rows, after)
    assert store.leaf(1).metrics == cli_json("model", "build", tmp_path / "session-1.markers.json")["metrics"]
    # A plant's own item, and one of its full leaf's, by node.
    plant = cli_json("sessions", "show", 2, "--db", copy)
    full = next(l["node"] for l in plant["leaves"] if l["kind"] == "full")
    store.correct(2, "collar_diameter", value=9.5, who="kim", why="re-measured")
    with pytest.raises(leafdig.InputError, match=r"would move \d+\.\d mm, more than the 20\.0 mm"):
        store.correct(2, "marker", node=full, row=1, col=1, position=(1.0, 2.0, 3.0), who="kim", why="slipped")
    store.correct(2, "marker", node=full, row=1, col=1, position=(1.0, 2.0, 3.0), who="kim", why="slipped",
                  confirm=True)
    with pytest.raises(leafdig.InputError, match="frame is 'plant' or 'digitizer'"):
        store.correct(2, "marker", node=full, row=1, col=1, position=(1.0, 2.0, 3.0), who="kim", why="x",
                      frame="leaf")
    with pytest.raises(leafdig.InputError, match="captured one leaf: its points are corrected in the digitizer"):
        store.correct(1, "tip", position=(1.0, 2.0, 3.0), who="kim", why="x", frame="plant", confirm=True)
    with pytest.raises(leafdig.InputError, match="is a full leaf"):
        store.correct(2, "landmark", node=full, row=1, position=(1.0, 2.0, 3.0), who="kim", why="x")
    assert len(cli_json("sessions", "show", 2, "--db", copy)["corrections"]) == 2
    # Approved is final: no correction after it.
    store.approve(1, who="kim", why="checked against the photos")
    # Who decided what, and what each correction changed (issue 49): the CLI's own history.
    history = store.history(1)
    assert [h["action"] for h in history] == ["corrected", "approved"]
    assert history[0]["what"] == "marker" and (history[0]["row"], history[0]["col"]) == (2, 3)
    assert np.allclose(history[0]["from"]["position_mm"], before[1][2])
    assert np.allclose(history[0]["to"]["position_mm"], moved)
    assert history[0]["moved_mm"] == pytest.approx(float(np.linalg.norm([0.5, -0.25, 0.0])))
    assert history[0]["who"] == "kim" and history[0]["why"] == "the stylus slipped"
    assert history[1]["who"] == "kim" and history[1]["why"] == "checked against the photos"
    assert history == cli_json("sessions", "show", 1, "--db", copy)["history"]
    assert [h["action"] for h in store.history(2)] == ["corrected", "corrected"]
    assert store.history(2)[0]["to"] == {"value_mm": 9.5}
    with pytest.raises(leafdig.InputError, match="approved"):
        store.correct(1, "marker", row=2, col=3, position=before[1][2], who="kim", why="back")
    # Until a curator reopens it, saying why: then the correction, and a decision again.
    with pytest.raises(leafdig.InputError, match="say why the session is reopened"):
        store.reopen(1, who="kim", why=" ")
    with pytest.raises(leafdig.InputError, match="only an approved or rejected session is reopened"):
        store.reopen(2, who="kim", why="not decided yet")
    store.reopen(1, who="lee", why="the marker was right after all")
    assert store.sessions(status="complete")[0]["id"] == 1
    store.correct(1, "marker", row=2, col=3, position=before[1][2], who="lee", why="back")
    store.reject(1, who="lee", why="row 2 disagrees with the photo")
    history = store.history(1)
    assert [h["action"] for h in history] == ["corrected", "approved", "reopened", "corrected", "rejected"]
    assert history[2]["reopens"] == "approved" and history[2]["who"] == "lee"
    assert history == cli_json("sessions", "show", 1, "--db", copy)["history"]


def test_the_lab_servers_roles_hold_through_python(lab, station):
    reader = leafdig.open(lab["reader"])
    sessions = reader.sessions()
    assert sorted(s["kind"] for s in sessions) == ["leaf", "plant"]
    leaf_id = reader.sessions(kind="leaf")[0]["id"]
    # The server's leaf is the station's leaf, number for number.
    assert reader.leaf(leaf_id).metrics == leafdig.open(station).leaf(1).metrics
    assert reader.events(leaf_id)[-1]["kind"] == "status"
    # A reader and a technician decide nothing, even opened writable; a curator approves.
    for role in ("reader", "technician"):
        with pytest.raises(leafdig.StoreError):
            leafdig.open(lab[role], writable=True).approve(leaf_id, who=role)
    assert reader.sessions(id=leaf_id)[0]["status"] == "complete"
    # So with corrections: the technician's refused by the server, the curator's taken.
    moved = reader.markers(leaf_id).rows[0][0] + np.array([0.1, 0.0, 0.0])
    with pytest.raises(leafdig.StoreError):
        leafdig.open(lab["technician"], writable=True).correct(leaf_id, "marker", row=1, col=1, position=moved,
                                                               who="tech", why="mine")
    leafdig.open(lab["curator"], writable=True).correct(leaf_id, "marker", row=1, col=1, position=moved,
                                                        who="carla", why="slipped")
    assert np.array_equal(reader.markers(leaf_id).rows[0][0], moved)
    leafdig.open(lab["curator"], writable=True).approve(leaf_id, who="carla")
    assert reader.sessions(id=leaf_id)[0]["status"] == "approved"
    # The password never shows in what the store says of itself.
    assert "s3cret" not in repr(reader)


def test_hostile_inputs_are_refused_by_the_cores_own_checks(tmp_path):
    """Issue 47, 21 and 22: a plan that is a device or a FIFO is refused by the C++ reader's
    checks (not read until memory runs out, not waited on), and a light that is not a
    direction is refused instead of leaving the leaf unlit."""
    with pytest.raises(ValueError, match="not a regular file"):
        leafdig.build_plant("/dev/zero")
    fifo = tmp_path / "plan.fifo"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="a named pipe"):
        leafdig.build_plant(str(fifo))
    for light in [(float("nan"), 0.0, 1.0), (0.0, 0.0, 0.0)]:
        with pytest.raises(ValueError, match="light"):
            leafdig.build_leaf(str(SAMPLES[0]), light=light)
    # A light of 1e200 is a direction like any other: the leaf is lit as by (1, 0, 0).
    far = leafdig.build_leaf(str(SAMPLES[0]), light=(1e200, 0.0, 0.0))
    near = leafdig.build_leaf(str(SAMPLES[0]), light=(1.0, 0.0, 0.0))
    assert far.metrics == near.metrics


def test_a_plant_stopped_before_its_first_node_is_named_not_a_crash(tmp_path):
    """Issue 47, 17: a plant capture interrupted during its landmarks (Ctrl-C) is kept; reading
    it as a plant from Python says it holds no whole plant yet and how to go on — it used to
    crash the interpreter (the survey took the first node of none)."""
    import signal
    db = tmp_path / "stopped.sqlite"
    capture = subprocess.Popen([CLI, "plant", "capture", "--simulate", "--speed", "1", "--db", str(db)],
                               stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            listed = cli("sessions", "list", "--json", "--db", db, check=False) if db.exists() else None
            if listed is not None and listed.returncode == 0 and json.loads(listed.stdout or "[]"):
                break
            time.sleep(0.2)
        time.sleep(1.0)  # a landmark or two at real speed: node 1 is many presses away
    finally:
        capture.send_signal(signal.SIGINT)
        capture.wait(timeout=60)
    store = leafdig.open(str(db))
    with pytest.raises(Exception, match="holds no whole plant yet"):
        store.plant(1)


def test_a_station_files_field_checks_are_read_as_field_list_reads_them(station, tmp_path):
    db = tmp_path / "field.sqlite"
    r = subprocess.run([CLI, "field", "check", "--simulate", "--speed", "20", "--json", "--db", str(db),
                        "--distortion", str(SOURCE / "data/fields/steel-bench.field.json")],
                       stdin=subprocess.DEVNULL, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    said = json.loads(r.stdout.strip().splitlines()[-1])
    checks = leafdig.open(str(db)).field_checks()
    assert len(checks) == 1
    got = checks[0]
    assert got["calibration_id"] == said["calibration_id"] == 1
    assert got["verdict"] == said["verdict"] == "correctable"
    assert got["rms_mm"] == pytest.approx(said["rms_mm"])
    assert got["correction"]["model"] == said["correction"]["model"]
    # An edited check (the append-only trigger dropped by an insider) is not trusted.
    con = sqlite3.connect(str(db))
    con.executescript("DROP TRIGGER field_checks_no_update; UPDATE field_checks SET verdict = 'pass';")
    con.close()
    with pytest.raises(leafdig.StoreError):
        leafdig.open(str(db)).field_checks()
    # A file without checks has none.
    assert leafdig.open(str(station)).field_checks() == []


def test_a_tip_calibration_is_read_as_field_tips_reads_it_and_a_rehashed_edit_is_refused(tmp_path):
    db = tmp_path / "tip.sqlite"
    r = subprocess.run([CLI, "field", "tip", "--simulate", "--sim-tip", "0,0,60", "--speed", "20", "--json",
                        "--db", str(db)], stdin=subprocess.DEVNULL, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    said = json.loads(r.stdout.strip().splitlines()[-1])
    tips = leafdig.open(str(db)).tip_calibrations()
    assert len(tips) == 1
    assert tips[0]["verdict"] == said["verdict"] == "pass"
    assert tips[0]["tip_mm"] == pytest.approx(said["tip_mm"])
    assert tips[0]["tip_mm"][2] == pytest.approx(60.0, abs=0.5)
    # An insider moves the tip and recomputes the chain's hash (docs/schema.md's formula): the
    # chain verifies, but the samples do not give that tip, so the calibration is not trusted.
    con = sqlite3.connect(str(db))
    row = con.execute("SELECT c.id, c.station, o.name, d.kind, d.port, c.created_utc, c.verdict, c.record_json, "
                      "c.prev_hash FROM tip_calibrations c JOIN operators o ON o.id = c.operator_id "
                      "JOIN devices d ON d.id = c.device_id").fetchone()
    record = json.loads(row[7])
    record["tip_mm"] = [0.0, 0.0, 0.0]
    text = json.dumps(record)
    fields = [row[8], str(row[0]), row[1], row[2], row[3], row[4], row[5], row[6], text]
    blob = "leafdig tip calibration/1\n" + "".join(f"{len(v.encode())}:{v}\n" for v in fields)
    digest = hashlib.sha256(blob.encode()).hexdigest()
    con.executescript("DROP TRIGGER tip_calibrations_no_update;")
    con.execute("UPDATE tip_calibrations SET record_json = ?, hash = ?", (text, digest))
    con.executescript("CREATE TRIGGER tip_calibrations_no_update BEFORE UPDATE ON tip_calibrations\n"
                      "  BEGIN SELECT RAISE(ABORT, 'tip calibrations are append-only: calibrate again'); END;")
    con.commit()
    con.close()
    with pytest.raises(leafdig.InputError, match="its tip is not what its samples give"):
        leafdig.open(str(db)).tip_calibrations()


def test_every_public_method_of_the_python_classes_says_what_it_does():
    # Issue 51: most of Store, Leaf and Plant had no docstring; help() is a modeller's first stop.
    for cls in (leafdig.Store, leafdig.Leaf, leafdig.Plant, leafdig.Mesh):
        for name, member in vars(cls).items():
            if name.startswith("_"):
                continue
            target = member.fget if isinstance(member, property) else member
            if callable(target):
                assert (target.__doc__ or "").strip(), "%s.%s has no docstring" % (cls.__name__, name)
