"""mbx from Python: translate CAD assemblies into multibody mechanisms, export,
simulate and calibrate them through the SDK's C API (``libmbx``).

The package is pure Python over :mod:`ctypes` (docs/python.md says why): it
loads ``libmbx.so.0`` (``MBX_LIBRARY`` may name the file, or the folder
holding it, e.g. a build tree's ``build/lib``) and, for file inputs,
``libmbx_files.so.0`` beside it. Arrays come back as NumPy arrays.

A quick tour::

    import mbx
    arm = mbx.translate("five_axis_arm.xml", shapes="five_axis_arm_a.wrl")
    print(arm.summary.dof, [f.message for f in arm.findings])
    arm.export("out/arm")                    # Modelica, MJCF, URDF, meshes
    arm.attach_drives("five_axis_arm_drives.xml")
    sim = arm.simulation()
    sim.initialize()
    traj = sim.record(stop_time=2.0, output_step=0.01)
    traj.q[:, sim.joint("waist").q_index]    # a NumPy column

Every failure of the SDK raises :class:`MbxError`, which carries the SDK's
message and the subject it names (joint, body, file and line).
"""
import ctypes
import json
import os
import weakref
from dataclasses import dataclass, field
from typing import List, Optional, Sequence

import numpy as np

from . import _lib
from ._lib import lib as _c

__all__ = [
    "MbxError", "version", "abi_version", "translate", "Mechanism", "Summary", "RigidBody", "Joint", "Finding",
    "Drive", "Simulation", "SimJoint", "Energy", "DriveSignals", "SimStats", "Trajectory", "read_trajectory_csv",
    "Calibration", "CalibrationSummary", "Cause", "Parameter",
    "STATUS_NAMES", "SUBJECT_KINDS", "EXPORT_FORMATS", "INTEGRATORS",
]

#: Status codes of ``mbx.h`` by value.
STATUS_NAMES = {0: "MBX_OK", 1: "MBX_ERROR_INVALID_ARGUMENT", 2: "MBX_ERROR_HOST_CALLBACK",
                3: "MBX_ERROR_INVALID_INPUT", 4: "MBX_ERROR_CANCELLED", 5: "MBX_ERROR_IO",
                6: "MBX_ERROR_OUT_OF_MEMORY", 7: "MBX_ERROR_VERSION", 8: "MBX_ERROR_INTERNAL",
                9: "MBX_ERROR_SIMULATION"}
#: ``mbx_subject_kind`` values as the strings this package uses.
SUBJECT_KINDS = {0: "none", 1: "body", 2: "frame", 3: "constraint", 4: "rigid_body", 5: "loop", 6: "file",
                 7: "model"}
#: Export format names for :meth:`Mechanism.export` and their ``mbx_export_format`` bits.
EXPORT_FORMATS = {"modelica": 1, "mjcf": 2, "urdf": 4, "meshes": 8}
_MESH_FORMATS = {"stl": 0, "obj": 1, "gltf": 2}
#: Integrator names for :meth:`Mechanism.simulation` and their ``mbx_integrator`` values.
INTEGRATORS = {"rk4": 0, "euler": 1, "accurate": 2}
_SEVERITIES = {0: "info", 1: "warning", 2: "error"}
_PRIMITIVES = {0: "weld", 1: "prismatic", 2: "revolute", 3: "spherical"}
_SIM_JOINT_KINDS = {0: "revolute", 1: "prismatic", 2: "spherical", 3: "fixed", 4: "free"}
_RIGID_BODY_KINDS = {0: "ground", 1: "dynamic", 2: "joint_node"}
_SET_GRAVITY = 1


def _s(b: Optional[bytes]) -> str:
    return b.decode("utf-8", "replace") if b else ""


def _b(text) -> Optional[bytes]:
    return None if text is None else os.fsencode(text)


class MbxError(Exception):
    """A failed SDK call: the SDK's message and what it is about.

    Attributes: ``status`` (int), ``status_name`` (e.g.
    ``"MBX_ERROR_INVALID_INPUT"``), ``message`` (the SDK's full sentence),
    ``subject_kind`` (one of :data:`SUBJECT_KINDS`' values), ``subject_id``,
    ``subject_name``, ``file`` and ``line`` (0 if unknown). ``str(error)`` is
    the message, prefixed by ``file:line:`` when the SDK named a file.
    """

    def __init__(self, status, message, subject_kind="none", subject_id="", subject_name="", file="", line=0):
        self.status = int(status)
        self.status_name = STATUS_NAMES.get(self.status, f"status {self.status}")
        self.message = message
        self.subject_kind = subject_kind
        self.subject_id = subject_id
        self.subject_name = subject_name
        self.file = file
        self.line = int(line)
        where = f"{file}:{line}: " if file and line else (f"{file}: " if file else "")
        super().__init__(f"{where}{message} ({self.status_name})")


class _Context:
    """One mbx_context: the error state of the calls made with it. The SDK
    asks that one context is used from one thread at a time; each Mechanism
    owns its own."""

    def __init__(self):
        handle = ctypes.c_void_p()
        status = _c.mbx_context_create(ctypes.byref(handle))
        if status != 0:
            raise MbxError(status, "mbx_context_create failed")
        self.handle = handle

    def check(self, status):
        """Raises MbxError for a failed status, with the context's error."""
        if status == 0:
            return
        info = _lib.new(_lib.ErrorInfo)
        if _c.mbx_context_last_error_info(self.handle, ctypes.byref(info)) != 0:
            raise MbxError(status, _s(_c.mbx_context_last_error(self.handle)) or STATUS_NAMES.get(status, ""))
        raise MbxError(status, _s(info.message), SUBJECT_KINDS.get(info.subject_kind, "none"), _s(info.subject_id),
                       _s(info.subject_name), _s(info.file), info.line)

    def close(self):
        if self.handle:
            _c.mbx_context_destroy(self.handle)
            self.handle = None


def _check_handle(status, what):
    """For calls without a context (queries): the status is all there is."""
    if status != 0:
        raise MbxError(status, f"{what} failed")


def version() -> str:
    """The library's version string, e.g. ``"0.1.0"``."""
    return _s(_c.mbx_version())


def abi_version() -> int:
    """The ABI version the loaded library implements (``MBX_ABI_VERSION``)."""
    return int(_c.mbx_abi_version())


# --------------------------------------------------------------------------
# Mechanism queries
# --------------------------------------------------------------------------
@dataclass
class Summary:
    """The mechanism's counts and mobility (``mbx_mechanism_summary``)."""
    part_count: int
    rigid_body_count: int
    joint_node_count: int
    joint_count: int
    revolute_count: int
    prismatic_count: int
    spherical_count: int
    weld_count: int
    cut_joint_count: int
    loop_count: int
    planar_loop_count: int
    collapsed_weld_loop_count: int
    dof: int
    gruebler_dof: int
    redundant_constraint_count: int
    floating_body_count: int
    warning_count: int
    error_count: int
    cad_part_count: int


@dataclass
class RigidBody:
    """One rigid body (``mbx_rigid_body_info``), SI. Index 0 is the ground.
    ``com`` and ``inertia`` (3x3, about the centre of mass) are in the body
    frame; ``position`` and ``rotation`` (3x3) its world pose at the CAD
    assembly configuration."""
    index: int
    kind: str
    name: str
    id: str
    part_count: int
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    parent_joint: int


@dataclass
class Joint:
    """One primitive joint of the mechanism (``mbx_joint_info``), SI:
    ``axis`` and ``position`` (of the joint frame) in world at the CAD pose."""
    index: int
    type: str
    name: str
    constraint_id: str
    primitive_index: int
    parent: int
    child: int
    is_cut: bool
    reversed: bool
    axis: np.ndarray
    position: np.ndarray
    rotation: np.ndarray
    limits: Optional[tuple]
    loop: int


@dataclass
class Finding:
    """One finding of the report (``mbx_finding``): ``severity`` is
    ``"info"``, ``"warning"`` or ``"error"``; ``code`` the stable code name."""
    severity: str
    code: str
    subject_kind: str
    subject_id: str
    subject_name: str
    message: str
    file: str
    line: int


@dataclass
class Drive:
    """A drive resolved against the mechanism (``mbx_drive_info``): every
    quantity at the joint, SI."""
    index: int
    name: str
    joint: int
    linear: bool
    motor_name: str
    transmission_name: str
    ratio: float
    efficiency: float
    armature: float
    effort_limit: float
    velocity_limit: float
    output_limit: float
    torque_constant: float
    stall_torque: float
    no_load_speed: float
    rotor_inertia: float
    servo_stiffness: float
    servo_damping: float
    emf_damping: float
    motion_point_count: int


def _fields(struct, names):
    return {n: getattr(struct, n) for n in names}


def translate(path, shapes=None, mesh_dirs: Sequence = (), mass_check: bool = True, length_tolerance: float = 0.0,
              centroid_tolerance: float = 0.0, package_paths=None, floating_base: bool = False) -> "Mechanism":
    """Translates a CAD export into a :class:`Mechanism`, as ``mbx translate``
    does. Its format is told from its XML root element or extension, as
    ``mbx formats`` lists (today SimMechanics first-generation XML, PMXML).

    ``shapes`` names a VRML97 scene whose shapes are matched to the bodies by
    pose; ``mesh_dirs`` are searched for the mesh files the XML names after
    its own folder. For a URDF, ``package_paths`` maps ROS package names to
    folders (``{"name": dir}``, as ``--package-path name=dir``; then
    ROS_PACKAGE_PATH), ``floating_base`` frees its root link, and its joint
    dynamics and collision shapes are attached as its description (docs/urdf.md).
    ``mass_check`` compares every closed mesh's centroid with
    the CAD centre of mass (findings ``mass_mismatch``). Tolerances of 0 take
    the SDK's defaults. Raises :class:`MbxError` naming the file and line for
    an unreadable input.
    """
    return Mechanism._from_file(path, shapes, mesh_dirs, mass_check, length_tolerance, centroid_tolerance,
                                dict(package_paths or {}), floating_base)


class Mechanism:
    """A translated mechanism: its report (summary, bodies, joints,
    findings), exports, drives, and the simulations and calibrations built
    from it. Make one with :func:`translate`. Use it from one thread at a
    time; :meth:`close` (or ``with``) frees it early."""

    def __init__(self):
        raise TypeError("use mbx.translate(...) to make a Mechanism")

    @classmethod
    def _from_file(cls, path, shapes, mesh_dirs, mass_check, length_tolerance, centroid_tolerance,
                   package_paths=None, floating_base=False):
        self = object.__new__(cls)
        self._handle = None
        self._files = None
        self._children = []
        self._ctx = _Context()
        self.source = os.fspath(path)
        try:
            self._open_files(path, shapes, mesh_dirs, package_paths or {}, floating_base)
            options = _lib.new(_lib.TranslateOptions)
            options.length_tolerance = length_tolerance
            options.centroid_tolerance = centroid_tolerance
            options.flags = 1 if mass_check else 0
            handle = ctypes.c_void_p()
            self._ctx.check(_c.mbx_translate(self._ctx.handle, _lib.files_lib().mbx_files_host(self._files),
                                             ctypes.byref(options), ctypes.byref(handle)))
            self._handle = handle
            self._own_description = _s(_lib.files_lib().mbx_files_description(self._files))
            if self._own_description:
                self.attach_drives(None)
        except BaseException:
            self.close()
            raise
        self.source = os.fspath(path)
        return self

    def _open_files(self, path, shapes, mesh_dirs, package_paths, floating_base):
        files = _lib.files_lib()
        options = _lib.new(_lib.FilesOptions)
        options.shapes = _b(shapes)
        dirs = [os.fsencode(d) for d in mesh_dirs]
        array = (ctypes.c_char_p * max(1, len(dirs)))(*dirs)
        options.mesh_dirs = array
        options.mesh_dir_count = len(dirs)
        packages = [os.fsencode(name) + b"=" + os.fsencode(d) for name, d in package_paths.items()]
        package_array = (ctypes.c_char_p * max(1, len(packages)))(*packages)
        options.package_paths = package_array
        options.package_path_count = len(packages)
        options.floating_base = 1 if floating_base else 0
        error = _lib.new(_lib.FilesError)
        handle = ctypes.c_void_p()
        if files.mbx_files_open(_b(path), ctypes.byref(options), ctypes.byref(handle), ctypes.byref(error)) != 0:
            raise MbxError(3, _s(error.message), "file", "", "", _s(error.file), error.line)
        self._files = handle

    def close(self):
        """Frees the mechanism, its file host and context, and every
        simulation and calibration made from it. Idempotent."""
        # Simulations borrow the mechanism's context and model: they go first.
        for ref in reversed(getattr(self, "_children", [])):
            child = ref()
            if child is not None:
                child.close()
        self._children = []
        if getattr(self, "_handle", None):
            _c.mbx_mechanism_destroy(self._handle)
            self._handle = None
        if getattr(self, "_files", None):
            _lib.files_lib().mbx_files_close(self._files)
            self._files = None
        if getattr(self, "_ctx", None):
            self._ctx.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def _live(self):
        if not self._handle:
            raise MbxError(1, "the mechanism was closed")
        return self._handle

    # -- report ------------------------------------------------------------
    @property
    def summary(self) -> Summary:
        """The counts and mobility of the mechanism (:class:`Summary`)."""
        s = _lib.new(_lib.MechanismSummary)
        _check_handle(_c.mbx_mechanism_get_summary(self._live(), ctypes.byref(s)), "mbx_mechanism_get_summary")
        return Summary(**_fields(s, Summary.__dataclass_fields__))

    @property
    def rigid_bodies(self) -> List[RigidBody]:
        """Every rigid body, the ground (index 0) first, then the dynamic
        bodies, then joint nodes."""
        s = self.summary
        out = []
        for i in range(1 + s.rigid_body_count + s.joint_node_count):
            r = _lib.new(_lib.RigidBodyInfo)
            _check_handle(_c.mbx_mechanism_get_rigid_body(self._live(), i, ctypes.byref(r)),
                          "mbx_mechanism_get_rigid_body")
            out.append(RigidBody(i, _RIGID_BODY_KINDS.get(r.kind, str(r.kind)), _s(r.name), _s(r.id), r.part_count,
                                 r.mass, np.array(r.com[:]), np.array(r.inertia[:]).reshape(3, 3),
                                 np.array(r.pose.position[:]), np.array(r.pose.rotation[:]).reshape(3, 3),
                                 r.parent_joint))
        return out

    @property
    def joints(self) -> List[Joint]:
        """Every primitive joint (tree and cut), in the SDK's index order."""
        out = []
        for i in range(self.summary.joint_count):
            j = _lib.new(_lib.JointInfo)
            _check_handle(_c.mbx_mechanism_get_joint(self._live(), i, ctypes.byref(j)), "mbx_mechanism_get_joint")
            out.append(Joint(i, _PRIMITIVES.get(j.type, str(j.type)), _s(j.name), _s(j.constraint_id),
                             j.primitive_index, j.parent, j.child, bool(j.is_cut), bool(j.reversed),
                             np.array(j.axis[:]), np.array(j.frame.position[:]),
                             np.array(j.frame.rotation[:]).reshape(3, 3),
                             (j.lower, j.upper) if j.has_limits else None, j.loop))
        return out

    def find_part(self, part_id: str) -> int:
        """Index of the rigid body the CAD part ``part_id`` ended up in."""
        index = ctypes.c_uint32()
        status = _c.mbx_mechanism_find_part(self._live(), part_id.encode(), ctypes.byref(index))
        if status != 0:
            raise MbxError(status, f"no CAD part '{part_id}' in the mechanism", "body", part_id)
        return index.value

    @property
    def findings(self) -> List[Finding]:
        """The report's findings (what the translation and exports noticed)."""
        out = []
        for i in range(_c.mbx_mechanism_finding_count(self._live())):
            f = _lib.new(_lib.Finding)
            _check_handle(_c.mbx_mechanism_get_finding(self._live(), i, ctypes.byref(f)), "mbx_mechanism_get_finding")
            out.append(Finding(_SEVERITIES.get(f.severity, str(f.severity)), _s(f.code_name),
                               SUBJECT_KINDS.get(f.subject_kind, "none"), _s(f.subject_id), _s(f.subject_name),
                               _s(f.message), _s(f.file), f.line))
        return out

    def write_report(self, directory) -> dict:
        """Writes ``report.json`` and ``report.txt`` into ``directory``
        (created) and returns report.json, parsed."""
        self._ctx.check(_c.mbx_mechanism_write_report(self._ctx.handle, self._live(), _b(directory)))
        with open(os.path.join(directory, "report.json"), encoding="utf-8") as f:
            return json.load(f)

    # -- export ------------------------------------------------------------
    def export(self, directory, formats: Sequence[str] = ("modelica", "mjcf", "urdf", "meshes"),
               mesh_format: str = "stl", model_name: Optional[str] = None, stop_time: float = 0.0) -> None:
        """Exports below ``directory`` (created): any of ``"modelica"``,
        ``"mjcf"``, ``"urdf"``, ``"meshes"`` (docs/exporters.md). ``mesh_format``
        is ``"stl"``, ``"obj"`` or ``"gltf"``; ``stop_time`` the Modelica
        experiment's (0: 10 s). What a format cannot express becomes a
        finding (see :attr:`findings`)."""
        options = _lib.new(_lib.ExportOptions)
        try:
            options.formats = sum(EXPORT_FORMATS[f] for f in set(formats))
            options.mesh_format = _MESH_FORMATS[mesh_format]
        except KeyError as e:
            raise MbxError(1, f"unknown export or mesh format {e.args[0]!r}") from None
        if not options.formats:
            raise MbxError(1, "no export format given")
        options.model_name = _b(model_name)
        options.stop_time = stop_time
        self._ctx.check(_c.mbx_mechanism_export(self._ctx.handle, self._live(), ctypes.byref(options), _b(directory)))

    def update_urdf(self, path, urdf=None) -> None:
        """Writes the URDF this mechanism was read from (``urdf``, default
        :attr:`source`) to ``path`` with the attached description's joint
        dynamics and body corrections in it, every other byte as it was
        (docs/urdf.md): after ``calibrate``, ``attach_drives(dir +
        "/description.xml")`` then ``update_urdf(...)`` gives the calibrated
        URDF. What URDF cannot hold becomes a finding."""
        source = self.source if urdf is None else urdf
        self._ctx.check(_c.mbx_mechanism_update_urdf(self._ctx.handle, self._live(), _b(os.fspath(source)),
                                                     _b(os.fspath(path))))

    def write_view(self, directory, trajectory=None, title: Optional[str] = None) -> str:
        """Writes ``directory/view.html`` (docs/view.md): the assembly in a
        browser, offline, playing ``trajectory`` (a trajectory.csv simulated
        from this mechanism) when given. Returns the page's path."""
        options = _lib.new(_lib.ViewOptions)
        options.trajectory = _b(trajectory)
        options.title = _b(title)
        self._ctx.check(_c.mbx_mechanism_write_view(self._ctx.handle, self._live(), ctypes.byref(options),
                                                    _b(directory)))
        return os.path.join(os.fspath(directory), "view.html")

    # -- drives ------------------------------------------------------------
    def attach_drives(self, drives=None, libraries: Sequence = ()) -> None:
        """Attaches the drives and joint dynamics of a description file
        (``--drives``, docs/mechatronics.md), loading the object ``libraries``
        first (the file's own libraries load by themselves). ``None``
        detaches every drive. What the input itself describes (a URDF's joint
        dynamics and collision shapes) stays, under the file's refinements.
        Raises :class:`MbxError` listing every problem."""
        own = getattr(self, "_own_description", "")
        if drives is None and not libraries and not own:
            self._ctx.check(_c.mbx_mechanism_set_mechatronics(self._ctx.handle, self._live(), None))
            self.drives_file = None
            return
        handle = ctypes.c_void_p()
        self._ctx.check(_c.mbx_mechatronics_create(self._ctx.handle, ctypes.byref(handle)))
        try:
            if own:
                self._ctx.check(_c.mbx_mechatronics_load_drives_text(self._ctx.handle, handle, _b(own),
                                                                     _b(self.source)))
            for library in libraries:
                self._ctx.check(_c.mbx_mechatronics_load_library(self._ctx.handle, handle, _b(library)))
            if drives is not None:
                self._ctx.check(_c.mbx_mechatronics_load_drives(self._ctx.handle, handle, _b(drives)))
            self._ctx.check(_c.mbx_mechanism_set_mechatronics(self._ctx.handle, self._live(), handle))
        finally:
            _c.mbx_mechatronics_destroy(handle)
        self.drives_file = None if drives is None else os.fspath(drives)

    @property
    def drives(self) -> List[Drive]:
        """The attached drives, resolved (:class:`Drive`)."""
        out = []
        for i in range(_c.mbx_mechanism_drive_count(self._live())):
            d = _lib.new(_lib.DriveInfo)
            _check_handle(_c.mbx_mechanism_get_drive(self._live(), i, ctypes.byref(d)), "mbx_mechanism_get_drive")
            values = _fields(d, [n for n in Drive.__dataclass_fields__ if n not in ("index", "linear")])
            for n in ("name", "motor_name", "transmission_name"):
                values[n] = _s(values[n])
            out.append(Drive(index=i, linear=bool(d.linear), **values))
        return out

    def drive_target(self, drive: int, time: float) -> np.ndarray:
        """Motion target of drive ``drive`` at ``time``: position, velocity,
        acceleration (SI)."""
        out = (ctypes.c_double * 3)()
        status = _c.mbx_mechanism_drive_target(self._live(), drive, time, out)
        if status != 0:
            raise MbxError(status, f"no drive {drive} (the mechanism has {len(self.drives)})")
        return np.array(out[:])

    # -- simulation and calibration -----------------------------------------
    def simulation(self, integrator: str = "rk4", step: float = 0.0, tolerance: float = 0.0,
                   gravity: Optional[Sequence[float]] = None) -> "Simulation":
        """Builds a :class:`Simulation` of the mechanism with its attached
        drives. ``integrator`` is ``"rk4"``, ``"euler"`` or ``"accurate"``
        (CVODE, stick/slip friction); ``step`` 0 means 1 ms; ``gravity``
        (m/s^2, world) defaults to 9.81 along -z."""
        if integrator not in INTEGRATORS:
            raise MbxError(1, f"unknown integrator {integrator!r} (one of {', '.join(INTEGRATORS)})")
        options = _lib.new(_lib.SimOptions)
        options.integrator = INTEGRATORS[integrator]
        options.step = step
        options.tolerance = tolerance
        if gravity is not None:
            options.flags = _SET_GRAVITY
            options.gravity[:] = [float(g) for g in gravity]
        sim = Simulation(self, options)
        self._children.append(weakref.ref(sim))
        return sim

    def calibrate(self, experiment, description=None, directory=None,
                  gravity: Optional[Sequence[float]] = None) -> "Calibration":
        """Calibrates the mechanism (with its attached drives) against the
        measured records an experiment file names (docs/calibration.md).
        ``description`` is the drives file the mechanism's drives came from
        (default: the one :meth:`attach_drives` loaded), extended into
        ``directory``/description.xml when ``directory`` is given (with
        calibration.json and calibration.html)."""
        options = _lib.new(_lib.CalibrateOptions)
        options.experiment = _b(experiment)
        if description is None:
            description = getattr(self, "drives_file", None)
        options.description = _b(description)
        options.directory = _b(directory)
        if gravity is not None:
            options.flags = _SET_GRAVITY
            options.gravity[:] = [float(g) for g in gravity]
        handle = ctypes.c_void_p()
        self._ctx.check(_c.mbx_calibrate(self._ctx.handle, self._live(), ctypes.byref(options), ctypes.byref(handle)))
        return Calibration(handle)  # outlives the mechanism (mbx.h)


# --------------------------------------------------------------------------
# Simulation
# --------------------------------------------------------------------------
@dataclass
class SimJoint:
    """A simulated joint (``mbx_sim_joint_info``): its coordinates are
    ``q[q_index:q_index+nq]`` and ``v[v_index:v_index+nv]``."""
    index: int
    name: str
    constraint_id: str
    kind: str
    mechanism_joint: int
    q_index: int
    v_index: int
    nq: int
    nv: int


@dataclass
class Energy:
    """Energies at the current state, J (``mbx_sim_energy``)."""
    kinetic: float
    gravity: float
    spring: float
    total: float


@dataclass
class DriveSignals:
    """A drive's signals at the current state (``mbx_sim_drive_signals``):
    joint target, controller output, armature current (A), joint effort."""
    target: float
    output: float
    current: float
    effort: float


@dataclass
class SimStats:
    """Work counters of a simulation (``mbx_sim_stats``)."""
    steps: int
    evaluations: int
    mode_switches: int
    max_closure_residual: float


@dataclass
class Trajectory:
    """A recorded run: ``time`` (N,), ``q`` (N, nq), ``v`` (N, nv), and per
    drive (N, drives) ``drive_target``, ``drive_output``, ``drive_current``,
    ``drive_effort``. ``joints`` and ``drive_names`` name the columns."""
    time: np.ndarray
    q: np.ndarray
    v: np.ndarray
    drive_target: np.ndarray
    drive_output: np.ndarray
    drive_current: np.ndarray
    drive_effort: np.ndarray
    joints: List[SimJoint] = field(default_factory=list)
    drive_names: List[str] = field(default_factory=list)

    def joint_q(self, name_or_id: str) -> np.ndarray:
        """The first position coordinate of a joint (by report name or CAD
        constraint id) over time."""
        for j in self.joints:
            if name_or_id in (j.name, j.constraint_id) and j.nq:
                return self.q[:, j.q_index]
        raise KeyError(name_or_id)

    def drive(self, name: str) -> int:
        """Column of drive ``name`` in the drive_* arrays."""
        return self.drive_names.index(name)


class Simulation:
    """mbx's own forward dynamics of a mechanism (docs/simulation.md): a
    model and one state. Coordinates are joint coordinates, zero at the CAD
    pose. Make one with :meth:`Mechanism.simulation`."""

    def __init__(self, mechanism: Mechanism, options):
        self._mechanism = mechanism  # keeps its context and mechanism alive
        self._ctx = mechanism._ctx
        self._model = None
        self._data = None
        model = ctypes.c_void_p()
        self._ctx.check(_c.mbx_sim_model_create(self._ctx.handle, mechanism._live(), ctypes.byref(options),
                                                ctypes.byref(model)))
        self._model = model
        data = ctypes.c_void_p()
        try:
            self._ctx.check(_c.mbx_sim_data_create(self._ctx.handle, model, ctypes.byref(data)))
        except BaseException:
            self.close()
            raise
        self._data = data
        info = _lib.new(_lib.SimModelInfo)
        _check_handle(_c.mbx_sim_model_get_info(model, ctypes.byref(info)), "mbx_sim_model_get_info")
        self.nq, self.nv = info.nq, info.nv
        #: Number of drives and of loop closures of the model.
        self.drive_count = info.drive_count
        self.loop_closure_count = info.loop_closure_count
        self.gravity = np.array(info.gravity[:])
        self.joints: List[SimJoint] = []
        for i in range(info.joint_count):
            j = _lib.new(_lib.SimJointInfo)
            _check_handle(_c.mbx_sim_model_get_joint(model, i, ctypes.byref(j)), "mbx_sim_model_get_joint")
            self.joints.append(SimJoint(i, _s(j.name), _s(j.constraint_id), _SIM_JOINT_KINDS.get(j.kind, str(j.kind)),
                                        j.mechanism_joint, j.q_index, j.v_index, j.nq, j.nv))
        self.drive_names = [d.name for d in mechanism.drives]

    def close(self):
        """Frees the state and the model. Idempotent."""
        if self._data:
            _c.mbx_sim_data_destroy(self._data)
            self._data = None
        if self._model:
            _c.mbx_sim_model_destroy(self._model)
            self._model = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def _live(self):
        if not self._data:
            raise MbxError(1, "the simulation was closed")
        return self._data

    def joint(self, name_or_id: str) -> SimJoint:
        """A simulated joint by report name or CAD constraint id."""
        index = ctypes.c_uint32()
        status = _c.mbx_sim_model_find_joint(self._model, name_or_id.encode(), ctypes.byref(index))
        if status != 0:
            raise MbxError(status, f"no single simulated joint named '{name_or_id}'", "constraint", name_or_id)
        return self.joints[index.value]

    def _joint_index(self, joint) -> int:
        return joint.index if isinstance(joint, SimJoint) else (
            joint if isinstance(joint, int) else self.joint(joint).index)

    def initialize(self, positions: Optional[dict] = None, velocities: Optional[dict] = None) -> None:
        """Time 0 at the CAD pose at rest, then the given coordinates
        (``{joint: value}`` with a joint's name, id or index; a sequence
        value sets several coordinates of one joint); the others are solved
        so that every loop closes."""
        values = []
        for mapping, is_velocity in ((positions or {}, 0), (velocities or {}, 1)):
            for joint, value in mapping.items():
                for k, x in enumerate(np.atleast_1d(np.asarray(value, dtype=float))):
                    values.append(_lib.SimFixedValue(self._joint_index(joint), k, is_velocity, float(x)))
        array = (_lib.SimFixedValue * max(1, len(values)))(*values)
        self._ctx.check(_c.mbx_sim_initialize(self._ctx.handle, self._live(), array, len(values)))

    @property
    def time(self) -> float:
        """Simulated time, s."""
        t = ctypes.c_double()
        _check_handle(_c.mbx_sim_get_state(self._live(), ctypes.byref(t), None, None), "mbx_sim_get_state")
        return t.value

    @property
    def q(self) -> np.ndarray:
        """Position coordinates (nq,), a copy."""
        q = np.zeros(self.nq)
        _check_handle(_c.mbx_sim_get_state(self._live(), None, q.ctypes.data_as(_lib.c_double_p), None),
                      "mbx_sim_get_state")
        return q

    @property
    def v(self) -> np.ndarray:
        """Velocity coordinates (nv,), a copy."""
        v = np.zeros(self.nv)
        _check_handle(_c.mbx_sim_get_state(self._live(), None, None, v.ctypes.data_as(_lib.c_double_p)),
                      "mbx_sim_get_state")
        return v

    def _array(self, values, n, what) -> np.ndarray:
        a = np.ascontiguousarray(values, dtype=float)
        if a.shape != (n,):
            raise MbxError(1, f"{what} needs {n} values, got shape {a.shape}")
        return a

    def set_state(self, q=None, v=None, time: Optional[float] = None) -> None:
        """Sets the whole state (omitted parts keep their values). Does not
        close loops (:meth:`initialize` does); refuses non-finite values
        naming the joint."""
        t = self.time if time is None else float(time)
        qa = self._array(self.q if q is None else q, self.nq, "q")
        va = self._array(self.v if v is None else v, self.nv, "v")
        self._ctx.check(_c.mbx_sim_set_state(self._ctx.handle, self._live(), t, qa.ctypes.data_as(_lib.c_double_p),
                                             va.ctypes.data_as(_lib.c_double_p)))

    def joint_state(self, joint):
        """(q, v) of one joint as arrays."""
        j = self.joints[self._joint_index(joint)]
        q, v = np.zeros(j.nq), np.zeros(j.nv)
        _check_handle(_c.mbx_sim_get_joint_state(self._live(), j.index, q.ctypes.data_as(_lib.c_double_p),
                                                 v.ctypes.data_as(_lib.c_double_p)), "mbx_sim_get_joint_state")
        return q, v

    def set_joint_state(self, joint, q=None, v=None) -> None:
        """Sets one joint's coordinates (None keeps them)."""
        j = self.joints[self._joint_index(joint)]
        qa = None if q is None else self._array(np.atleast_1d(q), j.nq, f"joint '{j.name}' q")
        va = None if v is None else self._array(np.atleast_1d(v), j.nv, f"joint '{j.name}' v")
        self._ctx.check(_c.mbx_sim_set_joint_state(
            self._ctx.handle, self._live(), j.index, None if qa is None else qa.ctypes.data_as(_lib.c_double_p),
            None if va is None else va.ctypes.data_as(_lib.c_double_p)))

    def set_effort(self, effort) -> None:
        """External effort per velocity coordinate (nv,), held until changed."""
        e = self._array(effort, self.nv, "effort")
        self._ctx.check(_c.mbx_sim_set_effort(self._ctx.handle, self._live(), e.ctypes.data_as(_lib.c_double_p)))

    def set_drive_target(self, drive, target: float) -> None:
        """Target of a drive (index or name) from now on; NaN returns it to
        its motion program."""
        index = self.drive_names.index(drive) if isinstance(drive, str) else int(drive)
        self._ctx.check(_c.mbx_sim_set_drive_target(self._ctx.handle, self._live(), index, float(target)))

    def step(self, count: int = 1) -> None:
        """``count`` steps of the model's step. Raises :class:`MbxError`
        (``MBX_ERROR_SIMULATION``, naming joint and time) when the run
        diverges; the state is then the last good one."""
        self._ctx.check(_c.mbx_sim_step(self._ctx.handle, self._live(), int(count)))

    def integrate(self, time: float) -> None:
        """Advances to ``time`` (s) exactly."""
        self._ctx.check(_c.mbx_sim_integrate(self._ctx.handle, self._live(), float(time)))

    def inverse_dynamics(self, qacc) -> np.ndarray:
        """Joint efforts (nv,) giving acceleration ``qacc`` at the current
        state (gravity and armature included, loops ignored)."""
        a = self._array(qacc, self.nv, "qacc")
        out = np.zeros(self.nv)
        self._ctx.check(_c.mbx_sim_inverse_dynamics(self._ctx.handle, self._live(), a.ctypes.data_as(_lib.c_double_p),
                                                    out.ctypes.data_as(_lib.c_double_p)))
        return out

    def forward_dynamics(self) -> np.ndarray:
        """Acceleration (nv,) at the current state under every force and the loops."""
        out = np.zeros(self.nv)
        self._ctx.check(_c.mbx_sim_forward_dynamics(self._ctx.handle, self._live(),
                                                    out.ctypes.data_as(_lib.c_double_p)))
        return out

    def mass_matrix(self) -> np.ndarray:
        """Joint-space mass matrix (nv, nv), armature included."""
        out = np.zeros((self.nv, self.nv))
        self._ctx.check(_c.mbx_sim_mass_matrix(self._ctx.handle, self._live(), out.ctypes.data_as(_lib.c_double_p)))
        return out

    def energy(self) -> Energy:
        """Kinetic, gravity, spring and total energy at the current state."""
        e = _lib.new(_lib.SimEnergy)
        self._ctx.check(_c.mbx_sim_get_energy(self._ctx.handle, self._live(), ctypes.byref(e)))
        return Energy(e.kinetic, e.gravity, e.spring, e.total)

    def drive_signals(self, drive) -> DriveSignals:
        """Signals of a drive (index or name) at the current state."""
        index = self.drive_names.index(drive) if isinstance(drive, str) else int(drive)
        s = _lib.new(_lib.SimDriveSignals)
        status = _c.mbx_sim_get_drive_signals(self._live(), index, ctypes.byref(s))
        if status != 0:
            raise MbxError(status, f"no drive {drive!r} (the model has {self.drive_count})")
        return DriveSignals(s.target, s.output, s.current, s.effort)

    def stats(self) -> SimStats:
        """Steps, evaluations, friction mode switches, largest closure residual."""
        s = _lib.new(_lib.SimStats)
        _check_handle(_c.mbx_sim_get_stats(self._live(), ctypes.byref(s)), "mbx_sim_get_stats")
        return SimStats(s.steps, s.evaluations, s.mode_switches, s.max_closure_residual)

    def record(self, stop_time: float, output_step: float = 0.01) -> Trajectory:
        """Integrates from the current state to ``stop_time`` (absolute, s),
        sampling the state and every drive's signals every ``output_step``
        (the current state is the first sample), and returns them as a
        :class:`Trajectory` of NumPy arrays."""
        if not output_step > 0:
            raise MbxError(1, f"output_step must be > 0, got {output_step}")
        t0 = self.time
        count = int(np.floor((stop_time - t0) / output_step + 1e-9)) + 1
        times = t0 + output_step * np.arange(count)
        if times[-1] < stop_time - 1e-12:
            times = np.append(times, stop_time)
        n, d = len(times), self.drive_count
        q, v = np.zeros((n, self.nq)), np.zeros((n, self.nv))
        sig = np.zeros((4, n, d))
        for k, t in enumerate(times):
            if k:
                self.integrate(t)
            q[k], v[k] = self.q, self.v
            for i in range(d):
                s = self.drive_signals(i)
                sig[:, k, i] = (s.target, s.output, s.current, s.effort)
        return Trajectory(times, q, v, sig[0], sig[1], sig[2], sig[3], list(self.joints), list(self.drive_names))

    def run(self, directory, stop_time: float, output_step: float = 0.0) -> None:
        """``mbx_sim_run``: integrates for ``stop_time`` seconds after the
        current time and writes ``trajectory.csv`` and ``simulation.json``
        into ``directory`` as one unit (read them back with
        :func:`read_trajectory_csv`)."""
        options = _lib.new(_lib.SimRunOptions)
        options.stop_time = stop_time
        options.output_step = output_step
        self._ctx.check(_c.mbx_sim_run(self._ctx.handle, self._live(), ctypes.byref(options), _b(directory)))


def read_trajectory_csv(path) -> dict:
    """Reads a ``trajectory.csv`` written by :meth:`Simulation.run` or
    ``mbx simulate``: a dict from column name to a NumPy array."""
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header)}


# --------------------------------------------------------------------------
# Calibration
# --------------------------------------------------------------------------
@dataclass
class CalibrationSummary:
    """Errors in percent, 100 ||y - y_model|| / ||y||, before and after, on
    the fit and validation records (``mbx_calibration_summary``).
    ``noise_level`` is the validation records' own effort noise after the
    filter, in the same measure (nan when no record holds an effort)."""
    cause_count: int
    warning_count: int
    baseline_fit_error: float
    baseline_validation_error: float
    final_fit_error: float
    final_validation_error: float
    baseline_simulated_fit_error: float
    baseline_simulated_validation_error: float
    final_simulated_fit_error: float
    final_simulated_validation_error: float
    noise_level: float
    wall_time: float
    explained_to_noise: int  # 1: what is left is noise; 0: it stands above; -1: noise not measured
    residual_note_count: int


@dataclass
class Parameter:
    """A fitted parameter, SI, with its standard error."""
    name: str
    value: float
    std_error: float


@dataclass
class Cause:
    """A named cause the model lacked (``mbx_calibration_cause``) with its
    fitted parameters and the errors after it was added."""
    name: str
    subject_kind: str
    subject_id: str
    subject_name: str
    evidence: str
    written: bool
    fit_error: float
    validation_error: float
    simulated_fit_error: float
    simulated_validation_error: float
    parameters: List[Parameter]


class Calibration:
    """The result of :meth:`Mechanism.calibrate`: ``summary``, ``causes``
    (with parameters), ``warnings`` and ``residual_notes``, read once from
    the SDK."""

    def __init__(self, handle):
        self._handle = handle
        s = _lib.new(_lib.CalibrationSummary)
        _check_handle(_c.mbx_calibration_get_summary(handle, ctypes.byref(s)), "mbx_calibration_get_summary")
        self.summary = CalibrationSummary(**_fields(s, CalibrationSummary.__dataclass_fields__))
        self.causes: List[Cause] = []
        for i in range(s.cause_count):
            c = _lib.new(_lib.CalibrationCause)
            _check_handle(_c.mbx_calibration_get_cause(handle, i, ctypes.byref(c)), "mbx_calibration_get_cause")
            parameters = []
            for k in range(c.parameter_count):
                p = _lib.new(_lib.CalibrationParameter)
                _check_handle(_c.mbx_calibration_get_parameter(handle, i, k, ctypes.byref(p)),
                              "mbx_calibration_get_parameter")
                parameters.append(Parameter(_s(p.name), p.value, p.std_error))
            self.causes.append(Cause(_s(c.name), SUBJECT_KINDS.get(c.subject_kind, "none"), _s(c.subject_id),
                                     _s(c.subject_name), _s(c.evidence), bool(c.written), c.fit_error,
                                     c.validation_error, c.simulated_fit_error, c.simulated_validation_error,
                                     parameters))
        self.warnings: List[str] = []
        while True:
            w = _c.mbx_calibration_get_warning(handle, len(self.warnings))
            if w is None:
                break
            self.warnings.append(_s(w))
        # Where the residual above the noise lies, in words.
        self.residual_notes: List[str] = [_s(_c.mbx_calibration_get_residual_note(handle, i))
                                          for i in range(s.residual_note_count)]

    def close(self):
        """Frees the SDK's result (everything read stays). Idempotent."""
        if self._handle:
            _c.mbx_calibration_destroy(self._handle)
            self._handle = None

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass
