"""Every public name of the package says what it is (docs/python.md)."""
import inspect

import mbx


def public_members(obj):
    for name, member in inspect.getmembers(obj):
        if name.startswith("_"):
            continue
        yield name, member


def test_every_public_name_has_a_docstring():
    missing = []
    assert mbx.__doc__ and len(mbx.__doc__) > 100
    for name in mbx.__all__:
        obj = getattr(mbx, name)
        if isinstance(obj, dict):
            continue  # constant tables, documented by their #: comments and docs/python.md
        doc = (obj.__doc__ or "").strip()
        # A dataclass without a docstring gets its signature as one: not documentation.
        if not doc or doc.startswith(f"{name}("):
            missing.append(name)
        if inspect.isclass(obj):
            for member_name, member in public_members(obj):
                if inspect.isfunction(member) or isinstance(member, property):
                    if not (member.__doc__ or "").strip():
                        missing.append(f"{name}.{member_name}")
    assert missing == []


def test_the_exception_carries_the_sdk_fields():
    e = mbx.MbxError(3, "joint 'x' is bad", "constraint", "x:1", "x", "f.xml", 7)
    assert (e.status_name, e.subject_kind, e.subject_id, e.subject_name, e.file, e.line) == (
        "MBX_ERROR_INVALID_INPUT", "constraint", "x:1", "x", "f.xml", 7)
    assert str(e).startswith("f.xml:7: joint 'x' is bad")
