"""Frozen functions of a scene that take the scene's Dr.Jit variables, not the scene (issue 10).

The device pass (``pipeline.device_pass``) is recorded once with ``dr.freeze`` and replayed in
later frames. On every call, Dr.Jit 1.5's frozen function walks its inputs to find the variables
its recording reads, and walks them again after the replay to assign its inputs back. Given the
``mi.Scene``, each walk visits every object through every path that reaches it (a BSDF once per
shape that uses it, an emitter through its shape and through the scene's list) and, since the
scene holds arrays of shape, emitter and sensor pointers, every registered instance of those
classes once more (``FlatVariables::traverse_with_registry``: a virtual call is recorded for
every registered instance, so their members are inputs too). The 226-object scene, batched into
18 shapes, is visited 3441 times per walk, registry included, for 269 distinct variables besides
the sensor's (``SceneVariables.visits`` and its handles; docs/results, issue 10, stop 30): the replay of a function that does nothing with the scene took 0.57-0.71 ms on an H200's host,
against 0.17-0.20 ms given the same variables as a flat tuple (``scripts/trace_overhead.py``'s
``frozen_replay``, four processes; docs/results, issue 10, stop 30).

:class:`FrozenScene` takes those variables once: the scene's and every registered instance's of
the classes the scene points to (but the sensor's: the sensor stays an input of every call, since
a camera moves), each once, as plain ``UInt32`` handles (Dr.Jit reads only their
indices; no pointer array among them, so no registry walk). Its frozen functions are called with
that tuple where the scene was, and read the scene itself from their binding: the same recording,
the same kernels, a fraction of the walk. (A pointer array among a function's other inputs, such
as a ``SurfaceInteraction3f``'s ``shape``, brings the registry walk back: the device pass takes
none.)

The handles are a snapshot. They keep the variables they were taken from, so an edit of the scene
through ``mi.traverse`` (which gives the edited objects new variables) is not seen by a replay:
after editing anything but the sensor, which stays a real input, or the geometry, whose edits
``api.rasterizer`` finds (and drops the snapshot with the rest of the scene's state), call
``hi.forget(scene)``. An instance registered after the snapshot (a
scene loaded later in the same process) is missing from it when a function records again; Dr.Jit
says so, and the variables are taken again once. Where the snapshot cannot serve (an
AD-attached scene variable, a Python plugin with Dr.Jit members outside Mitsuba's traversal, a
second failure), the functions take the scene itself and Dr.Jit walks it on every call: counted
in ``FrameStats.frozen_inputs`` as ``scene``. Where Dr.Jit cannot record the function given the
scene either, the functions run unfrozen from then on, counted as ``unfrozen``: Dr.Jit 1.5 refuses
any recording whose virtual call meets a BSDF registered outside the scene (``mi.load_dict`` of a
lone BSDF, before or after the scene: "traversal was skipped because no such object instance was
found in the function's inputs"; a frozen ``mi.render`` of Mitsuba 3.9.1's ``path`` fails the
same way; docs/results/gpu/issue10/stop67).

Most of the snapshot is not read by a given function: the trace call of ``scripts/trace_overhead.py``
reads 121 of the 226-object scene's 267 variables, and the walk of a variable costs as much
whether read or not (on an H200's host, the replay of a function that only takes them: 0.15–0.16
ms given the 267, 0.09–0.10 given the 121; docs/results/gpu/issue10/stop38). So each
:class:`FrozenFunction` learns which of them its first recording reads: that recording runs with
Dr.Jit's log at its ``Debug`` level, captured (Dr.Jit's module prints it to ``sys.stdout``), where
the recording names the input slot of every variable it reads (a kernel's parameters, a virtual
call's data); the scene's own few variables, through which an OptiX launch reads its shader
binding table, are always passed (:func:`read_set`). Its later calls pass only those variables
(``FrameStats.frozen_inputs``: ``read set``), which records once more (the same ``dr.freeze``
keeps both recordings: their inputs differ in layout). A recording with the set that Dr.Jit
refuses (one that reads a variable outside it: a new configuration of the same function; an input
Dr.Jit demands that no log line names) is made again with the whole snapshot, which the function
takes from then on (``FrozenFunction.missed`` keeps what Dr.Jit said).
"""
from __future__ import annotations

import contextlib
import gc
import io
import itertools
import re
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi

from .errors import HybridError

#: what Dr.Jit's recording says when one of its inputs is missing: a variable read but not found
#: among them, or a virtual call over instances whose members none of them holds
_MISSING = ("not specified as an input variable", "traversal was skipped")
_NO_ID = 2**31 - 1  # an instance id no registry reaches
#: the class whose instance the frozen functions take as an input of its own (the sensor): its
#: registered instances are not walked (the device pass calls the sensor it is given, no virtual
#: call over sensors)
_PASSED = "Sensor"


@dataclass(frozen=True)
class SceneVariables:
    """The distinct Dr.Jit variables of a scene and of the registered instances it points to."""

    handles: tuple  # one ``mi.UInt32`` per variable (of any type: the frozen function reads its index)
    visits: int  # what one walk of Dr.Jit's visits for the same objects (with repeats)
    #: the indices of the scene's own variables, none of an instance's (its acceleration structure's
    #: state: an OptiX launch reads its shader binding table through one of them, not as a parameter)
    own: frozenset = frozenset()


def scene_variables(scene: mi.Scene) -> SceneVariables | None:
    """The snapshot :class:`FrozenScene` passes for ``scene``, or ``None`` where it cannot be
    taken (a variable attached to Dr.Jit's AD graph, a class without a pointer type)."""
    indices: list[int] = []
    domains: list[str] = []

    def visit(index: int, variant: str, domain: str) -> None:
        indices.append(index)
        if domain and domain not in domains:
            domains.append(domain)

    walked: set[int] = set()
    sensor_variables: list[int] = []
    with dr.scoped_set_flag(dr.JitFlag.EnableObjectTraversal, True):
        scene._traverse_1_cb_ro(visit)
        of_scene = len(indices)
        for domain in domains:  # grows while instances point to other classes
            instances = [] if domain == _PASSED else _registered(domain)
            if instances is None:
                return None
            for instance in instances:
                if instance is not None and id(instance) not in walked:
                    walked.add(id(instance))
                    instance._traverse_1_cb_ro(visit)
        for sensor in scene.sensors():
            sensor._traverse_1_cb_ro(lambda index, *_: sensor_variables.append(index))
    if any(index >> 32 for index in indices):
        return None
    # 0: an unset member; a sensor's variables come with the sensor the function takes each call
    # (in the snapshot too, they would alias its variables until a camera change replaced them,
    # and the inputs' layout would change: one more recording)
    passed = set(sensor_variables)
    distinct = [index for index in dict.fromkeys(indices) if index and index not in passed]
    handles = variable_handles(distinct)
    own = frozenset(indices[:of_scene]) - frozenset(indices[of_scene:])
    return SceneVariables(handles=handles, visits=len(indices), own=own)


def variable_handles(indices) -> tuple:
    """One ``mi.UInt32`` per Dr.Jit variable index in ``indices`` (variables of any type): a frozen
    function's replay reads only the index of each input, so a flat tuple of these stands in for
    the objects that hold the variables, and is walked at a fraction of their nested cost."""
    indices = list(indices)
    return tuple(dr.detail.update_indices([mi.UInt32(0)] * len(indices), indices))


def _registered(domain: str) -> list | None:
    """Every instance registered with Dr.Jit in the class ``domain`` of this variant (``None``
    entries for freed ids), by id from 1 until the registry has no such id; ``None`` if Mitsuba
    has no pointer array for the class. (Dr.Jit looks an id up as null where the class never had
    an instance, and raises past the last id it has held where it had.)"""
    pointers = getattr(mi, f"{domain}Ptr", None)
    if pointers is None:
        return None

    def lookup(instance_id: int):
        return dr.reinterpret_array(pointers, mi.UInt32(instance_id))[0]

    try:
        lookup(_NO_ID)
        return []  # no instance of the class was ever registered
    except RuntimeError:
        pass
    instances = []
    for instance_id in itertools.count(1):
        try:
            instances.append(lookup(instance_id))
        except RuntimeError:  # past the last id the registry has held
            return instances


class _Bound:
    """``fn(scene, *args)`` called with the snapshot, or with the scene, in the scene's place: the
    methods that ``dr.freeze`` wraps (it walks the arguments and the globals a function names, not
    a bound method's ``self``)."""

    def __init__(self, scene: mi.Scene, fn):
        self.scene, self.fn = scene, fn

    def snapshot(self, variables: tuple, *args):
        return self.fn(self.scene, *args)

    def whole(self, scene: mi.Scene, *args):
        return self.fn(scene, *args)


class FrozenScene:
    """The frozen functions of one scene and the one snapshot of its variables they share."""

    def __init__(self, scene: mi.Scene):
        self.scene = scene
        self.variables: SceneVariables | None = None
        self.taken = 0  # snapshots taken (a second one: an instance registered since the first)
        self.whole = False  # the snapshot cannot serve: every function takes the scene itself
        #: what Dr.Jit said when it could not record a function given the scene itself either ("":
        #: never): from then on every function of the scene runs unfrozen
        self.unfrozen = ""

    @property
    def inputs(self) -> str:
        """What the functions take for the scene now: ``variables``, ``scene`` or ``unfrozen``."""
        return "unfrozen" if self.unfrozen else "scene" if self.whole else "variables"

    def freeze(self, fn) -> "FrozenFunction":
        """``fn(scene, *args)`` frozen, called as ``frozen(*args)`` (:class:`FrozenFunction`)."""
        return FrozenFunction(self, fn)

    def snapshot(self) -> SceneVariables | None:
        """The snapshot to pass, taken if there is none; ``None`` once it cannot serve. Garbage is
        collected first: the snapshot walks every instance registered in a class, and an instance
        of a scene that is garbage but not yet collected may hold variables already released by
        the collector's clearing of its cycle; Dr.Jit aborts the process on such an index
        ("jit_var(r967): unknown variable!", seen in the test suite: a case's scene walked the
        previous case's emitter). One collection per snapshot, which a scene takes once."""
        if self.variables is None and not self.whole:
            gc.collect()
            self.variables, self.taken = scene_variables(self.scene), self.taken + 1
            self.whole = self.variables is None
        return self.variables

    def missed(self) -> None:
        """A recording missed an input of the snapshot: the first time, take it again (an
        instance registered since); the second, give up on it."""
        self.variables, self.whole = None, self.taken > 1


def require_frozen(inputs: str, what: str) -> None:
    """A benchmark's check that ``what``, timed as a frozen replay, was one: a
    :class:`HybridError` where its frozen functions fell back to running unfrozen (``inputs``:
    ``FrameStats.frozen_inputs`` or :attr:`FrozenFunction.inputs`), whose times would be reported
    under the frozen frame's name."""
    if inputs == "unfrozen":
        raise HybridError(f"{what}: Dr.Jit could not record its frozen replay in this process (a BSDF "
                          "registered outside the scene, e.g. made with mi.load_dict, is met by its "
                          "virtual calls), so it would be timed unfrozen; delete such BSDFs before "
                          "loading the scene, or time it with freeze=False")


class FrozenFunction:
    """One frozen function of a :class:`FrozenScene`: it replays with the variables of the snapshot
    that its recording reads (learnt at its first call), with the whole snapshot where that set
    fell short, and with the scene itself once the snapshot cannot serve."""

    def __init__(self, owner: FrozenScene, fn):
        bound = _Bound(owner.scene, fn)
        self.owner = owner
        self.by_snapshot, self.by_scene, self.plain = dr.freeze(bound.snapshot), dr.freeze(bound.whole), bound.whole
        #: the snapshot the read set was learnt from, and the set (None: not learnt, or not usable)
        self._learnt: SceneVariables | None = None
        self.read: tuple | None = None
        self.missed = ""  # what Dr.Jit said when a recording with the read set failed ("": never)

    @property
    def inputs(self) -> str:
        """What the function takes for the scene now: ``read set``, ``variables``, ``scene`` or
        ``unfrozen`` (:attr:`FrozenScene.unfrozen`)."""
        if self.owner.inputs != "variables":
            return self.owner.inputs
        return "read set" if self.read is not None and self._learnt is self.owner.variables else "variables"

    def __call__(self, *args):
        while (variables := self.owner.snapshot()) is not None:
            try:
                with _collection_paused():
                    if self._learnt is not variables:  # the first call on this snapshot: learn what it reads
                        self._learnt, self.read = variables, None
                        with _recording_log() as log:
                            result = self.by_snapshot(variables.handles, *args)
                        self.read = read_set(log.getvalue(), variables)
                        return result
                    return self.by_snapshot(variables.handles if self.read is None else self.read, *args)
            except RuntimeError as error:
                # a recording with the read set that fails, for any reason Dr.Jit gives (a variable read
                # beyond the set; an input it demands that no log line names, as an OptiX launch's shader
                # binding table), is repeated with the whole snapshot, which stays from then on
                if self.read is not None and self._learnt is variables:
                    self.read, self.missed = None, str(error.__cause__ or error)[:300]
                    continue
                if not _missing_input(error):
                    raise
            self.owner.missed()
        if not self.owner.unfrozen:
            try:
                with _collection_paused():
                    return self.by_scene(self.owner.scene, *args)
            except RuntimeError as error:
                if not _missing_input(error):
                    raise
                self.owner.unfrozen = str(error.__cause__ or error)[:300]
        return self.plain(self.owner.scene, *args)

    @property
    def n_recordings(self) -> int:
        return self.by_snapshot.n_recordings + self.by_scene.n_recordings


def read_set(log: str, variables: SceneVariables) -> tuple | None:
    """The handles of ``variables`` that a recording read, from Dr.Jit 1.5's ``Debug`` log of it:
    ``Adding variable V <ptr> input i to slot sK`` maps each input variable to its slot; a slot is
    read where a kernel's parameter is recorded (``-> param sK``, ``<- param sK``) or a virtual
    call's data (``var at slot sK``). The scene's own variables (``SceneVariables.own``: its
    acceleration structure's state, a handful) are always kept: an OptiX launch reads its shader
    binding table through one of them, which the log does not name. ``None`` where the log holds
    no recording (another format: the whole snapshot is passed)."""
    if "Recording (n_inputs=" not in log:
        return None
    slots = {int(v): int(k) for v, k in re.findall(r"Adding variable (\d+) <[^>]*> input \d+ to slot s(\d+)", log)}
    read = {int(k) for k in re.findall(r"(?:-> param|<- param|var at slot) s(\d+)", log)}
    return tuple(h for h in variables.handles if slots.get(h.index) in read or h.index in variables.own)


@contextlib.contextmanager
def _recording_log():
    """Dr.Jit's log at its ``Debug`` level (which names what a recording reads, without the
    kernels' source that ``Trace`` adds), which its Python module prints to ``sys.stdout``, into
    a string instead while the block runs (``.getvalue()``); the level restored after."""
    level, log = dr.log_level(), io.StringIO()
    with contextlib.redirect_stdout(log):
        dr.set_log_level(dr.LogLevel.Debug)
        try:
            yield log
        finally:
            dr.set_log_level(level)


@contextlib.contextmanager
def _collection_paused():
    """Python's cyclic garbage collector off for a frozen call: run while Dr.Jit records, it can
    free a variable whose release is a host callback (such as NumPy memory Dr.Jit maps), which a
    recording cannot hold, and Dr.Jit aborts the process ("enqueue_host_func(): this function
    cannot be recorded"; seen in the test suite once recordings that miss an input, and are
    retried, left garbage behind). Garbage is collected after the call instead."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _missing_input(error: BaseException) -> bool:
    """Whether ``error`` (or one it was raised from) is Dr.Jit's recording missing an input."""
    while error is not None:
        if any(text in str(error) for text in _MISSING):
            return True
        error = error.__cause__
    return False
