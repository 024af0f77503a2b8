"""leafdig for modellers: the station's leaves and plants as numpy arrays and the numbers
the station shows (docs/python.md).

    import leafdig
    leaf = leafdig.build_leaf("data/samples/lower-leaf-n10.markers.json")
    leaf.metrics["blade_area_mm2"]          # equal to `leafdig model build --json`'s
    mesh = leaf.mesh()                      # vertices N×3, faces M×3, organs M, organ_names
    store = leafdig.open("station.sqlite")  # or postgresql://… (the server's roles apply)
    [s["id"] for s in store.sessions(status="approved")]

Errors carry the command line's words: ``InputError`` (a ``ValueError``) for bad input,
naming the file, row and point; ``StoreError`` for a store that refuses or does not verify;
``OSError`` for files that cannot be read or written.

Threads: the heavy calls (reading, building, meshing, metrics, exports, opening a store) run
without the GIL, so threads building different leaves run at once. A ``Leaf``, ``Plant`` or
``Markers`` may be read from several threads; a ``Store`` is used by one thread at a time.
"""

import errno as _errno
import json as _json
import os as _os

from . import _leafdig as _core
from ._leafdig import InputError, StoreError, Markers  # noqa: F401  (re-exported)

__version__ = _core.__version__
__all__ = ["__version__", "InputError", "StoreError", "Markers", "Leaf", "Plant", "Store", "Mesh",
           "read_markers", "build_leaf", "open", "build_plant", "grow", "import_plant", "synth_leaf"]


class Mesh:
    """A triangle mesh: ``vertices`` (N×3 float64, mm), ``normals`` (N×3, unit), ``faces``
    (M×3 integer indices into vertices, counter-clockwise seen from outside / the adaxial
    side), ``organs`` (M organ indices, one per face), ``organ_names`` (the organ of each
    index: "midrib", "lateral-1-right", …, "contour", "blade"; on a plant "stem" and each
    leaf's organs) and ``organ_ranks`` (the leaf rank of each organ; 0 the stem or a lone leaf).
    The arrays are copies made once from the C++ mesh, which keeps its organs apart."""

    def __init__(self, arrays):
        self.vertices = arrays["vertices"]
        self.normals = arrays["normals"]
        self.faces = arrays["faces"]
        self.organs = arrays["organs"]
        self.organ_names = list(arrays["organ_names"])
        self.organ_ranks = arrays["organ_ranks"]

    def __repr__(self):
        return "<leafdig.Mesh %d vertices, %d triangles, %d organs>" % (
            len(self.vertices), len(self.faces), len(self.organ_names))


class Leaf:
    """A leaf built by the method of seed 000 (ball B-spline veins, a B-spline blade).

    ``metrics``: a dict equal to the ``metrics`` of ``leafdig model build --json`` for the same
    markers and options (area, its 95 % interval, projected and silhouette area, STAR, …).
    ``mesh()``: a ``Mesh``. ``markers``: the ``Markers`` in the model's frame. ``model``: the
    leafdig.model/1 document (veins as 4-D B-splines, the blade surface) as a dict;
    ``vein(i, t)`` evaluates vein i (``vein_names``) at parameters t in [0, 1] as an array of
    (x, y, z, radius); ``blade(u, v)`` the blade surface. ``export(path)`` writes the file its
    extension names (.glb .obj .ply .stl, .can .mtg .csv .xml .vgx, .json the model document) and
    returns the paths written."""

    def __init__(self, core):
        self._core = core
        self._metrics = None
        self._mesh = None

    @property
    def metrics(self):
        """The leaf's metrics: ``leafdig model build --json``'s ``metrics`` for the same markers
        and options (blade and vein areas, the area's 95 % interval, projected and silhouette
        areas, STAR, lengths; mm, mm²)."""
        if self._metrics is None:
            self._metrics = _json.loads(self._core.metrics_json())
        return self._metrics

    @property
    def model(self):
        """The leafdig.model/1 document as a dict: veins as 4-D ball B-splines (x, y, z, radius),
        the blade surface, the thickness rule's values (mm)."""
        return _json.loads(self._core.model_json())

    @property
    def markers(self):
        """The ``Markers`` the leaf was built from, in the model's frame (mm)."""
        return self._core.markers

    @property
    def frame(self):
        """The frame the leaf is given in: ``"leaf"`` (base at the origin, midrib on +Y) or
        ``"digitizer"`` (as captured)."""
        return self._core.frame

    @property
    def vein_names(self):
        """The veins' names, in the order ``vein(i, t)`` numbers them ("midrib", then the
        laterals)."""
        return self._core.vein_names()

    def vein(self, index, t):
        """Vein ``index`` (a number, or its name) at parameters ``t``: an array (len(t), 4)."""
        if isinstance(index, str):
            index = self.vein_names.index(index)
        return self._core.vein(index, [float(x) for x in _iter(t)])

    def blade(self, u, v):
        """The blade surface at parameter pairs (u[k], v[k]) in [0, 1]: an array (len(u), 3)."""
        return self._core.blade([float(x) for x in _iter(u)], [float(x) for x in _iter(v)])

    def mesh(self):
        """The leaf's triangle mesh (a ``Mesh``: vertices in mm, faces, organ labels), built once
        and kept."""
        if self._mesh is None:
            self._mesh = Mesh(self._core.mesh())
        return self._mesh

    def export(self, path, light=(0.0, 0.0, 1.0)):
        """Writes the file ``path``'s extension names (.glb .obj .ply .stl, .can .mtg .csv .xml .vgx, .json
        the model document; ``light`` is the direction the silhouette is taken along) and returns
        the paths written."""
        return self._core.export(_os.fspath(path), tuple(float(x) for x in light))

    def __repr__(self):
        return "<leafdig.Leaf %s, blade %.1f mm²>" % (self.markers.id, self.metrics["blade_area_mm2"])


class Plant:
    """A plant built from a leafdig.plant/1 plan (``build_plant``): ``metrics`` (``area_mm2``,
    ``silhouette_mm2``, ``star``, as ``leafdig plant build --json``), ``leaves`` (one dict per
    leaf, as that JSON's), ``mesh()``, ``mtg()`` (the MTG text), ``caribu_scene()``
    (CARIBU's ``{label: [[(x,y,z),(x,y,z),(x,y,z)], …]}`` in metres, labels as in our .can
    file: optical species, plant, leaf rank, organ), ``export(path)``."""

    def __init__(self, core):
        self._core = core
        self._mesh = None

    @property
    def metrics(self):
        """The plant's metrics: ``area_mm2``, ``silhouette_mm2`` and ``star``, as ``leafdig plant
        build --json``."""
        return self._core.metrics()

    @property
    def leaves(self):
        """One dict per leaf (rank, insertion height, angles, area, …), as ``leafdig plant build
        --json``'s ``leaves``."""
        return self._core.leaves()

    @property
    def id(self):
        """The plant's id, from its plan."""
        return self._core.id

    @property
    def report(self):
        """For a plant from ``import_plant``: what was read — the file's entities (``vertices``, the
        root included, as OpenAlea counts them), the plant's by class, its ``points`` and
        ``axes_by_order``, and ``notes`` (what was kept in the file but not drawn); ``{}`` for
        a plant built or captured."""
        return _core.import_report(self._core)

    @property
    def time(self):
        """The growth time the plant was built at (``build_plant(plan, time=...)``, days), or None
        when it was built without one."""
        return self._core.time

    def mesh(self):
        """The plant's triangle mesh (a ``Mesh``: stem and leaves, mm), built once and kept."""
        if self._mesh is None:
            self._mesh = Mesh(self._core.mesh())
        return self._mesh

    def mtg(self):
        """The plant as MTG text (OpenAlea's reader takes it): a built plant's as ``leafdig plant
        build -o p.mtg`` writes it, a captured plant's (``Store.plant``) the survey's as
        ``leafdig sessions export`` writes it, an imported one's as ``leafdig plant import``."""
        return self._core.encode(".mtg")

    def csv(self):
        """The plant as CSV text, one row per MTG entity, as the command that makes the plant's
        MTG writes it (``plant build``, ``sessions export``, ``plant import``)."""
        return self._core.encode(".csv")

    def to_openalea(self):
        """The plant as an ``openalea.mtg.MTG``, read by OpenAlea's own reader from ``mtg()``
        (the text every MTG reader leafdig is tested against takes). Needs OpenAlea: without it,
        an ``ImportError`` saying so."""
        try:
            from openalea.mtg import io as _mtg_io
        except ImportError as e:
            raise ImportError("Plant.to_openalea needs OpenAlea's MTG package (openalea.mtg); without it, "
                              "write plant.mtg() to a file and read it where OpenAlea is installed") from e
        return _mtg_io.read_mtg(self.mtg())

    def caribu_scene(self):
        """CARIBU's scene, ready for ``caribu.CaribuScene(scene=...)``: ``{label: [[(x, y, z),
        (x, y, z), (x, y, z)], …]}`` in metres — each triangle a list of three point tuples, as
        CARIBU's scene check requires (it refuses tuples of tuples: "Unrecognised scene
        format")."""
        return {label: [list(t) for t in triangles] for label, triangles in self._core.caribu_scene().items()}

    def export(self, path):
        """Writes the file ``path``'s extension names (.glb .obj .ply .stl .can .mtg .csv .json, .xml Helios, .vgx VegeSTAR)
        and returns the paths written."""
        return self._core.export(_os.fspath(path))

    def __repr__(self):
        return "<leafdig.Plant %s, %d leaves>" % (self.id, len(self.leaves))


class Store:
    """A station's file or the lab server, read only unless opened with ``writable=True``
    (on the server, the login's role decides what it may do)."""

    def __init__(self, core):
        self._core = core

    def sessions(self, **filters):
        """Every session as a dict (id, kind, project, plant, leaf, type, status, operator,
        station, created, events, …); keyword filters keep those equal, e.g.
        ``sessions(status="approved", kind="leaf")``."""
        unknown = [k for k in filters if k not in _SESSION_KEYS]
        if unknown:
            raise InputError("sessions() has no filter %r: filter by %s" % (unknown[0], ", ".join(sorted(_SESSION_KEYS))))
        # A word a session never holds would silently match nothing (kind="leaves" gave []).
        for key, words in _SESSION_WORDS.items():
            if key in filters and filters[key] not in words:
                raise InputError("sessions(%s=%r) matches no session: a session's %s is one of %s"
                                 % (key, filters[key], key, ", ".join(words)))
        return [s for s in self._core.sessions() if all(s.get(k) == v for k, v in filters.items())]

    def markers(self, id, node=None):
        """A leaf session's markers (its chain verified first); with ``node``, a plant
        session's full leaf at that node (1 at the base), as ``sessions export --node`` writes
        it. ``InputError`` names the nodes that have a full leaf."""
        if node is not None and (isinstance(node, bool) or int(node) < 1):
            raise InputError("node is a plant's node number, 1 at the base (got %r)" % (node,))
        return self._core.markers(int(id), 0 if node is None else int(node))

    def leaf(self, id, node=None, **options):
        """A leaf session — or, with ``node``, a plant session's full leaf at that node — built
        as ``build_leaf`` builds markers (the same options)."""
        return build_leaf(self.markers(id, node=node), **options)

    def events(self, id):
        """The session's log, verified: dicts with seq, utc, mono_ns, kind, payload (a dict), raw, hash."""
        out = self._core.events(int(id))
        for e in out:
            e["payload"] = _json.loads(e["payload"])
        return out

    def plant_survey(self, id):
        """A plant session's survey (its frame, nodes and leaves with the measured angles) as a dict."""
        return _json.loads(self._core.plant_survey_json(int(id)))

    def plant(self, id, light=(0.0, 0.0, 1.0)):
        """A plant session's captured plant as a model (``Plant``): the stem through the
        digitized nodes, full leaves as digitized, quick leaves shaped from this store's
        approved leaves — the model ``sessions export`` writes (GLB, CARIBU, plant-model JSON)."""
        return Plant(self._core.plant(int(id), tuple(float(x) for x in light)))

    def history(self, id):
        """Every curator's decision, reopening and correction of the session, in the order
        they were written (its chain verified first): dicts with seq, utc, action
        ("approved", "rejected", "reopened" — with reopens, the decision it reopened — or
        "corrected"), who (on the lab server "NAME (login)" or the login) and why; a
        correction also what, row, col, from and to (``{"position_mm": [x, y, z]}`` or
        ``{"value_mm": v}``) and, for a point, moved_mm — what ``leafdig sessions show`` lists."""
        return _json.loads(self._core.history_json(int(id)))

    def field_checks(self):
        """The station file's field checks, oldest first (``leafdig field list --json``): dicts
        with calibration_id, created_utc, station, operator, device, jig, points, rms_mm, max_mm,
        worst_point, tolerance_mm, verdict and correction (model, holdout_rms_mm,
        holdout_max_mm). Each is trusted only when its numbers are what its presses give (else
        InputError); the chain of checks is verified first (else StoreError). A station's file
        only: the lab server holds no field checks."""
        return _json.loads(self._core.field_checks_json())

    def tip_calibrations(self):
        """The station file's tip (pivot) calibrations of the stylus, oldest first (``leafdig
        field tips --json``): dicts with calibration_id, created_utc, station, operator, device,
        samples, rejected, tip_mm, pivot_mm, rms_mm, max_mm, tilt_spread_deg, tolerance_mm and
        verdict. Each is trusted only when its samples give its numbers (else InputError); the
        chain is verified first (else StoreError). A station's file only."""
        return _json.loads(self._core.tip_calibrations_json())

    def approve(self, id, who, why=""):
        """Approves a complete session, saying why if you will (a curator's decision)."""
        return self._core.review(int(id), "approved", who, why)

    def reject(self, id, who, why):
        """Rejects a complete session, saying why (a curator's decision; a reason is required)."""
        return self._core.review(int(id), "rejected", who, why)

    def reopen(self, id, who, why):
        """Reopens an approved or rejected session, saying why (a curator's event, as
        ``leafdig sessions reopen``): it is complete again, to be corrected and decided anew;
        the history keeps the decision and the reopening. Returns the event's number; refusals
        raise ``InputError`` (no reason, a session not decided) or ``StoreError``."""
        return self._core.reopen(int(id), who, why)

    def correct(self, id, what, *, who, why, row=0, col=0, node=0, position=None, value=None, confirm=False,
                frame=None):
        """Corrects one item of a complete session, saying why, as ``leafdig sessions correct``
        does (a ``corrected`` event; the curator's role on the lab server). ``what`` is a
        leaf's item (``tip``, ``marker``, ``midrib_thickness``, ``vein_origin_thickness``,
        ``point_thickness``, ``edge_thickness``) or a plant's (``landmark``, ``collar``,
        ``collar_diameter``, ``point``, ``reading``, ``quick_point``); ``row``/``col`` number it
        as the CLI's ``--row``/``--col``; ``node`` names a plant's full leaf. A point takes
        ``position=(x, y, z)`` in mm, a reading ``value`` in mm; a point that would move more
        than 20 mm needs ``confirm=True`` (``InputError`` says how far). ``frame`` is the
        position's: ``"plant"`` (a plant session's default: as ``plant()``, the survey and every
        export give points) or ``"digitizer"`` (a leaf session's only one). Returns the event's
        number; refusals raise ``InputError`` (the item, the value, no reason) or ``StoreError``."""
        if frame is not None and frame not in ("plant", "digitizer"):
            raise InputError("frame is 'plant' or 'digitizer' (got %r)" % (frame,))
        if position is not None:
            position = tuple(float(v) for v in position)
            if len(position) != 3:
                raise InputError("position takes (x, y, z) in mm")
        return self._core.correct(int(id), str(what), int(row), int(col), int(node), position,
                                  None if value is None else float(value), who, why, bool(confirm),
                                  "" if frame is None else frame)

    def __repr__(self):
        return "<leafdig.Store %s>" % self._core.where


_SESSION_WORDS = {"kind": ("leaf", "plant"),
                  "status": ("open", "complete", "approved", "rejected", "abandoned")}
_SESSION_KEYS = {"id", "kind", "project", "plant", "leaf", "type", "status", "operator", "station",
                 "station_session_id", "created", "events", "measured_area_mm2"}


def _iter(x):
    try:
        return list(x)
    except TypeError:
        return [x]


def read_markers(path):
    """A leafdig.markers/1 file as ``Markers``: ``tip`` (3,), ``rows`` (N×7×3, tip row first),
    ``midrib_thickness``, ``vein_origin_thickness`` (N, NaN where not measured),
    ``point_thickness`` (N×7), ``edge_thickness``; ``rule_thickness()`` gives every marker's
    diameter after the thickness rule. Units: mm."""
    path = _os.fspath(path)
    if not _os.path.exists(path):
        raise FileNotFoundError(_errno.ENOENT, "no markers file here: check the path", path)
    return _core.read_markers(path)


def build_leaf(markers_or_path, blade="interp", resolution="export", mesh="uniform", max_error=None,
               frame="digitizer", light=(0.0, 0.0, 1.0)):
    """Builds a leaf as ``leafdig model build`` does with the same options: ``blade``
    interp|approx|bezier|nurbs, ``resolution`` paper|preview|export|reference, ``mesh``
    uniform|seed|adaptive (``max_error`` in mm for adaptive), ``frame`` digitizer|leaf."""
    if isinstance(markers_or_path, Markers):
        markers, source = markers_or_path, ""
    else:
        markers, source = read_markers(markers_or_path), _os.fspath(markers_or_path)
    return Leaf(_core.build_leaf(markers, source=source, blade=blade, resolution=resolution, mesh=mesh, max_error=max_error,
                                 frame=frame, light=tuple(float(x) for x in light)))


def open(path_or_url, writable=False):  # noqa: A001  (the name modellers asked for)
    """Opens a station's SQLite file or the lab server (``postgresql://…``)."""
    return Store(_core.open_store(_os.fspath(path_or_url), writable))


def _plan_text(plan):
    if isinstance(plan, dict):
        return _json.dumps(plan), "the plan given", _os.getcwd()
    path = _os.fspath(plan)
    try:
        # Read by the C++ core: a device (/dev/zero), a FIFO or a file beyond leafdig's size
        # bound is refused by name before anything is read, as every reader of leafdig does.
        text = _core.read_file(path).decode("utf-8")
    except UnicodeDecodeError:
        raise InputError("the plan %s is not UTF-8 text: save it as UTF-8 JSON" % path) from None
    return text, path, _os.path.dirname(_os.path.abspath(path))


def build_plant(plan, time=None, resolution="export"):
    """A plant from a leafdig.plant/1 plan (a path or a dict; relative paths in a dict are
    taken from the working directory), at growth time ``time`` (days) when given."""
    text, source, base = _plan_text(plan)
    return Plant(_core.build_plants(text, source, base, [time], resolution=resolution)[0])


def import_plant(path, units=None, drf=None, plant=1, resolution="export"):
    """A digitized plant from the archives — an AMAP / OpenAlea MTG file or a HydroShoot digitizing
    table — as a ``Plant``, read as ``leafdig plant import`` reads it (docs/plants.md, "Archives"):
    ``units`` is the unit of the file's coordinates after the dressing file's LengthUnit (``"mm"``,
    ``"cm"`` or ``"m"``: an MTG does not say it; a HydroShoot table is in cm unless given), ``drf``
    an MTG's dressing file, ``plant`` which plant of the file (1 the first). Its ``mtg()`` and
    ``csv()`` are the import's (axes ``A<n>`` of points ``E<k>``, each naming its entity and line in
    the archive); ``report`` says what was read."""
    core = _core.import_plant(_os.fspath(path), "" if drf is None else _os.fspath(drf),
                              "" if units is None else units, plant, resolution)
    return Plant(core)


def grow(plan, times, resolution="export"):
    """The plant at each of ``times`` (the plan needs its "growth")."""
    text, source, base = _plan_text(plan)
    return [Plant(p) for p in _core.build_plants(text, source, base, [float(t) for t in times], resolution=resolution)]


def synth_leaf(shape="tobacco", serration="none", rows=12, noise=0.0, seed=1, length=500.0):
    """A synthetic leaf (docs/synthetic-leaves.md): its ``Markers`` (with Gaussian noise of
    ``noise`` mm) and its truth (the leafdig.truth/1 document: exact area, …) as a dict."""
    markers, truth = _core.synth_leaf(shape, serration, int(rows), float(noise), int(seed), float(length))
    return markers, _json.loads(truth)
