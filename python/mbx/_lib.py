"""Loading libmbx (and libmbx_files) and the ctypes mirror of ``mbx/mbx.h``.

Internal: the public names are in :mod:`mbx`. Every structure here copies the
header's layout field by field; ABI rule 1 (fields only appended) is what lets
an older mirror keep working against a newer library, because each struct's
``struct_size`` tells the library how much of it this side knows.
"""
import ctypes
import ctypes.util
import os

c_double_p = ctypes.POINTER(ctypes.c_double)


class Pose(ctypes.Structure):
    """mbx_pose: position (m) and row-major rotation."""
    _fields_ = [("position", ctypes.c_double * 3), ("rotation", ctypes.c_double * 9)]


class ErrorInfo(ctypes.Structure):
    """mbx_error_info."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("status", ctypes.c_int), ("subject_kind", ctypes.c_int),
                ("subject_id", ctypes.c_char_p), ("subject_name", ctypes.c_char_p), ("file", ctypes.c_char_p),
                ("line", ctypes.c_int32), ("message", ctypes.c_char_p)]


class TranslateOptions(ctypes.Structure):
    """mbx_translate_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("length_tolerance", ctypes.c_double),
                ("orthonormality_tolerance", ctypes.c_double), ("rank_tolerance", ctypes.c_double),
                ("flags", ctypes.c_uint32), ("centroid_tolerance", ctypes.c_double)]


class MechanismSummary(ctypes.Structure):
    """mbx_mechanism_summary."""
    _fields_ = [("struct_size", ctypes.c_uint32)] + [(n, ctypes.c_uint32) for n in (
        "part_count", "rigid_body_count", "joint_node_count", "joint_count", "revolute_count", "prismatic_count",
        "spherical_count", "weld_count", "cut_joint_count", "loop_count", "planar_loop_count",
        "collapsed_weld_loop_count")] + [("dof", ctypes.c_int32), ("gruebler_dof", ctypes.c_int32)] + [
        (n, ctypes.c_uint32) for n in ("redundant_constraint_count", "floating_body_count", "warning_count",
                                       "error_count", "cad_part_count")]


class RigidBodyInfo(ctypes.Structure):
    """mbx_rigid_body_info."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("kind", ctypes.c_int), ("name", ctypes.c_char_p),
                ("id", ctypes.c_char_p), ("part_count", ctypes.c_uint32), ("mass", ctypes.c_double),
                ("com", ctypes.c_double * 3), ("inertia", ctypes.c_double * 9), ("pose", Pose),
                ("parent_joint", ctypes.c_int32)]


class JointInfo(ctypes.Structure):
    """mbx_joint_info."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("type", ctypes.c_int), ("name", ctypes.c_char_p),
                ("constraint_id", ctypes.c_char_p), ("primitive_index", ctypes.c_uint32),
                ("parent", ctypes.c_uint32), ("child", ctypes.c_uint32), ("is_cut", ctypes.c_int32),
                ("reversed", ctypes.c_int32), ("axis", ctypes.c_double * 3), ("frame", Pose),
                ("has_limits", ctypes.c_int32), ("lower", ctypes.c_double), ("upper", ctypes.c_double),
                ("loop", ctypes.c_int32)]


class Finding(ctypes.Structure):
    """mbx_finding."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("severity", ctypes.c_int), ("code", ctypes.c_int),
                ("subject_kind", ctypes.c_int), ("subject_id", ctypes.c_char_p), ("subject_name", ctypes.c_char_p),
                ("message", ctypes.c_char_p), ("code_name", ctypes.c_char_p), ("file", ctypes.c_char_p),
                ("line", ctypes.c_int32)]


class ExportOptions(ctypes.Structure):
    """mbx_export_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("formats", ctypes.c_uint32), ("mesh_format", ctypes.c_int),
                ("model_name", ctypes.c_char_p), ("stop_time", ctypes.c_double)]


class ViewOptions(ctypes.Structure):
    """mbx_view_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("trajectory", ctypes.c_char_p), ("title", ctypes.c_char_p)]


class DriveInfo(ctypes.Structure):
    """mbx_drive_info."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("name", ctypes.c_char_p), ("joint", ctypes.c_uint32),
                ("linear", ctypes.c_int32), ("motor_name", ctypes.c_char_p),
                ("transmission_name", ctypes.c_char_p)] + [(n, ctypes.c_double) for n in (
        "ratio", "efficiency", "armature", "effort_limit", "velocity_limit", "output_limit", "torque_constant",
        "stall_torque", "no_load_speed", "rotor_inertia", "servo_stiffness", "servo_damping", "emf_damping")] + [
        ("motion_point_count", ctypes.c_uint32)]


class SimOptions(ctypes.Structure):
    """mbx_sim_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("flags", ctypes.c_uint32), ("gravity", ctypes.c_double * 3),
                ("integrator", ctypes.c_int), ("step", ctypes.c_double), ("tolerance", ctypes.c_double)]


class SimModelInfo(ctypes.Structure):
    """mbx_sim_model_info."""
    _fields_ = [("struct_size", ctypes.c_uint32)] + [(n, ctypes.c_uint32) for n in (
        "nq", "nv", "joint_count", "drive_count", "loop_closure_count", "closure_rows")] + [
        ("gravity", ctypes.c_double * 3)]


class SimJointInfo(ctypes.Structure):
    """mbx_sim_joint_info."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("name", ctypes.c_char_p), ("constraint_id", ctypes.c_char_p),
                ("kind", ctypes.c_int), ("mechanism_joint", ctypes.c_int32), ("q_index", ctypes.c_uint32),
                ("v_index", ctypes.c_uint32), ("nq", ctypes.c_uint32), ("nv", ctypes.c_uint32)]


class SimFixedValue(ctypes.Structure):
    """mbx_sim_fixed_value (fixed layout, used in arrays)."""
    _fields_ = [("joint", ctypes.c_uint32), ("index", ctypes.c_uint32), ("velocity", ctypes.c_int32),
                ("value", ctypes.c_double)]


class SimEnergy(ctypes.Structure):
    """mbx_sim_energy."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("kinetic", ctypes.c_double), ("gravity", ctypes.c_double),
                ("spring", ctypes.c_double), ("total", ctypes.c_double)]


class SimDriveSignals(ctypes.Structure):
    """mbx_sim_drive_signals."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("target", ctypes.c_double), ("output", ctypes.c_double),
                ("current", ctypes.c_double), ("effort", ctypes.c_double)]


class SimStats(ctypes.Structure):
    """mbx_sim_stats."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("steps", ctypes.c_uint64), ("evaluations", ctypes.c_uint64),
                ("mode_switches", ctypes.c_uint64), ("max_closure_residual", ctypes.c_double)]


class SimRunOptions(ctypes.Structure):
    """mbx_sim_run_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("stop_time", ctypes.c_double), ("output_step", ctypes.c_double)]


class CalibrateOptions(ctypes.Structure):
    """mbx_calibrate_options."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("flags", ctypes.c_uint32), ("gravity", ctypes.c_double * 3),
                ("experiment", ctypes.c_char_p), ("description", ctypes.c_char_p), ("directory", ctypes.c_char_p)]


class CalibrationSummary(ctypes.Structure):
    """mbx_calibration_summary."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("cause_count", ctypes.c_uint32),
                ("warning_count", ctypes.c_uint32)] + [(n, ctypes.c_double) for n in (
        "baseline_fit_error", "baseline_validation_error", "final_fit_error", "final_validation_error",
        "baseline_simulated_fit_error", "baseline_simulated_validation_error", "final_simulated_fit_error",
        "final_simulated_validation_error", "noise_level", "wall_time")] + [
        ("explained_to_noise", ctypes.c_int32), ("residual_note_count", ctypes.c_uint32)]


class CalibrationCause(ctypes.Structure):
    """mbx_calibration_cause."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("name", ctypes.c_char_p), ("subject_kind", ctypes.c_int),
                ("subject_id", ctypes.c_char_p), ("subject_name", ctypes.c_char_p), ("evidence", ctypes.c_char_p),
                ("parameter_count", ctypes.c_uint32), ("written", ctypes.c_int32)] + [(n, ctypes.c_double) for n in (
        "fit_error", "validation_error", "simulated_fit_error", "simulated_validation_error")]


class CalibrationParameter(ctypes.Structure):
    """mbx_calibration_parameter."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("name", ctypes.c_char_p), ("value", ctypes.c_double),
                ("std_error", ctypes.c_double)]


class FilesOptions(ctypes.Structure):
    """mbx_files_options (mbx/mbx_files.h)."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("shapes", ctypes.c_char_p),
                ("mesh_dirs", ctypes.POINTER(ctypes.c_char_p)), ("mesh_dir_count", ctypes.c_uint32),
                ("package_paths", ctypes.POINTER(ctypes.c_char_p)), ("package_path_count", ctypes.c_uint32),
                ("floating_base", ctypes.c_int32)]


class FilesError(ctypes.Structure):
    """mbx_files_error (mbx/mbx_files.h)."""
    _fields_ = [("struct_size", ctypes.c_uint32), ("file", ctypes.c_char_p), ("line", ctypes.c_int32),
                ("message", ctypes.c_char_p)]


def new(struct_type):
    """A zeroed struct with struct_size set, as the header's ABI rules ask."""
    s = struct_type()
    s.struct_size = ctypes.sizeof(struct_type)
    return s


_P = ctypes.c_void_p
_S = ctypes.c_int  # mbx_status
_U = ctypes.c_uint32
_D = ctypes.c_double
_C = ctypes.c_char_p
_PU = ctypes.POINTER(ctypes.c_uint32)
_PD = c_double_p

# name: (restype, argtypes)
_PROTOTYPES = {
    "mbx_status_name": (_C, [_S]),
    "mbx_version": (_C, []),
    "mbx_abi_version": (_U, []),
    "mbx_context_create": (_S, [ctypes.POINTER(_P)]),
    "mbx_context_destroy": (None, [_P]),
    "mbx_context_last_error": (_C, [_P]),
    "mbx_context_last_error_info": (_S, [_P, ctypes.POINTER(ErrorInfo)]),
    "mbx_translate": (_S, [_P, _P, ctypes.POINTER(TranslateOptions), ctypes.POINTER(_P)]),
    "mbx_mechanism_destroy": (None, [_P]),
    "mbx_mechanism_release_host": (_S, [_P]),
    "mbx_mechanism_get_summary": (_S, [_P, ctypes.POINTER(MechanismSummary)]),
    "mbx_mechanism_get_rigid_body": (_S, [_P, _U, ctypes.POINTER(RigidBodyInfo)]),
    "mbx_mechanism_find_part": (_S, [_P, _C, _PU]),
    "mbx_mechanism_get_joint": (_S, [_P, _U, ctypes.POINTER(JointInfo)]),
    "mbx_mechanism_finding_count": (_U, [_P]),
    "mbx_mechanism_get_finding": (_S, [_P, _U, ctypes.POINTER(Finding)]),
    "mbx_mechanism_write_report": (_S, [_P, _P, _C]),
    "mbx_mechanism_export": (_S, [_P, _P, ctypes.POINTER(ExportOptions), _C]),
    "mbx_mechanism_update_urdf": (_S, [_P, _P, _C, _C]),
    "mbx_mechanism_write_view": (_S, [_P, _P, ctypes.POINTER(ViewOptions), _C]),
    "mbx_mechatronics_create": (_S, [_P, ctypes.POINTER(_P)]),
    "mbx_mechatronics_destroy": (None, [_P]),
    "mbx_mechatronics_load_library": (_S, [_P, _P, _C]),
    "mbx_mechatronics_load_drives": (_S, [_P, _P, _C]),
    "mbx_mechatronics_load_drives_text": (_S, [_P, _P, _C, _C]),
    "mbx_mechatronics_drive_count": (_U, [_P]),
    "mbx_mechanism_set_mechatronics": (_S, [_P, _P, _P]),
    "mbx_mechanism_drive_count": (_U, [_P]),
    "mbx_mechanism_get_drive": (_S, [_P, _U, ctypes.POINTER(DriveInfo)]),
    "mbx_mechanism_drive_target": (_S, [_P, _U, _D, _PD]),
    "mbx_sim_model_create": (_S, [_P, _P, ctypes.POINTER(SimOptions), ctypes.POINTER(_P)]),
    "mbx_sim_model_destroy": (None, [_P]),
    "mbx_sim_model_get_info": (_S, [_P, ctypes.POINTER(SimModelInfo)]),
    "mbx_sim_model_get_joint": (_S, [_P, _U, ctypes.POINTER(SimJointInfo)]),
    "mbx_sim_model_find_joint": (_S, [_P, _C, _PU]),
    "mbx_sim_data_create": (_S, [_P, _P, ctypes.POINTER(_P)]),
    "mbx_sim_data_destroy": (None, [_P]),
    "mbx_sim_initialize": (_S, [_P, _P, ctypes.POINTER(SimFixedValue), _U]),
    "mbx_sim_get_state": (_S, [_P, _PD, _PD, _PD]),
    "mbx_sim_set_state": (_S, [_P, _P, _D, _PD, _PD]),
    "mbx_sim_get_joint_state": (_S, [_P, _U, _PD, _PD]),
    "mbx_sim_set_joint_state": (_S, [_P, _P, _U, _PD, _PD]),
    "mbx_sim_set_effort": (_S, [_P, _P, _PD]),
    "mbx_sim_set_drive_target": (_S, [_P, _P, _U, _D]),
    "mbx_sim_step": (_S, [_P, _P, _U]),
    "mbx_sim_integrate": (_S, [_P, _P, _D]),
    "mbx_sim_inverse_dynamics": (_S, [_P, _P, _PD, _PD]),
    "mbx_sim_forward_dynamics": (_S, [_P, _P, _PD]),
    "mbx_sim_mass_matrix": (_S, [_P, _P, _PD]),
    "mbx_sim_get_energy": (_S, [_P, _P, ctypes.POINTER(SimEnergy)]),
    "mbx_sim_get_drive_signals": (_S, [_P, _U, ctypes.POINTER(SimDriveSignals)]),
    "mbx_sim_get_stats": (_S, [_P, ctypes.POINTER(SimStats)]),
    "mbx_sim_run": (_S, [_P, _P, ctypes.POINTER(SimRunOptions), _C]),
    "mbx_calibrate": (_S, [_P, _P, ctypes.POINTER(CalibrateOptions), ctypes.POINTER(_P)]),
    "mbx_calibration_destroy": (None, [_P]),
    "mbx_calibration_get_summary": (_S, [_P, ctypes.POINTER(CalibrationSummary)]),
    "mbx_calibration_get_cause": (_S, [_P, _U, ctypes.POINTER(CalibrationCause)]),
    "mbx_calibration_get_parameter": (_S, [_P, _U, _U, ctypes.POINTER(CalibrationParameter)]),
    "mbx_calibration_get_warning": (_C, [_P, _U]),
    "mbx_calibration_get_residual_note": (_C, [_P, _U]),
}

_FILES_PROTOTYPES = {
    "mbx_files_open": (ctypes.c_int, [_C, ctypes.POINTER(FilesOptions), ctypes.POINTER(_P),
                                      ctypes.POINTER(FilesError)]),
    "mbx_files_host": (_P, [_P]),
    "mbx_files_close": (None, [_P]),
    "mbx_files_description": (_C, [_P]),
}


def _candidates(env_var, soname):
    """Where to look for a library, first match wins: the environment
    variable (a file, or a folder holding it), the install beside this
    package (_paths.py, written at install), then the dynamic loader."""
    here = os.path.dirname(os.path.abspath(__file__))
    given = os.environ.get(env_var)
    if given:
        yield os.path.join(given, soname) if os.path.isdir(given) else given
        return
    try:
        from . import _paths  # only in an installed package
        yield os.path.normpath(os.path.join(here, _paths.LIBRARY_DIR_FROM_PACKAGE, soname))
    except ImportError:
        pass
    yield soname


def _load(env_var, soname, prototypes, first=None):
    errors = []
    paths = ([first] if first and not os.environ.get(env_var) else []) + list(_candidates(env_var, soname))
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError as e:
            errors.append(f"{path}: {e}")
            continue
        for name, (restype, argtypes) in prototypes.items():
            fn = getattr(lib, name)
            fn.restype = restype
            fn.argtypes = argtypes
        return lib
    raise ImportError(f"mbx: cannot load {soname} (set {env_var} to its path): " + "; ".join(errors))


lib = _load("MBX_LIBRARY", "libmbx.so.0", _PROTOTYPES)
_files_lib = None


def files_lib():
    """libmbx_files, loaded on first use: only file inputs need it. Looked
    for beside the libmbx that was loaded first (so MBX_LIBRARY pointing into
    a build tree finds the file host built there), unless MBX_FILES_LIBRARY
    names it."""
    global _files_lib
    if _files_lib is None:
        folder = os.path.dirname(lib._name)
        beside = os.path.join(folder, "libmbx_files.so.0") if folder else None
        if beside and not os.path.exists(beside):
            beside = None
        _files_lib = _load("MBX_FILES_LIBRARY", "libmbx_files.so.0", _FILES_PROTOTYPES, first=beside)
    return _files_lib
