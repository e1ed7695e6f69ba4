"""The type stubs name exactly what the module has, so editors complete every name."""

import ast
import pathlib

import inertia
from inertia import _inertia

STUB = pathlib.Path(__file__).parents[1] / "inertia" / "_inertia.pyi"


def stub_names():
    tree = ast.parse(STUB.read_text())
    names, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
            members[node.name] = {
                n.name for n in node.body if isinstance(n, ast.FunctionDef)
            } | {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        elif isinstance(node, ast.FunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
    return names, members


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_stub_lists_every_public_name_and_member():
    names, members = stub_names()
    assert public(_inertia) == names
    for name in names:
        obj = getattr(_inertia, name)
        if isinstance(obj, type):
            if issubclass(obj, BaseException):
                # Its attributes are set on each instance: the stub declares them.
                assert public(obj) - public(BaseException) <= members[name], name
            else:
                assert public(obj) == {m for m in members[name] if not m.startswith("_")}, name


def test_package_reexports_the_extension():
    assert inertia.World is _inertia.World
