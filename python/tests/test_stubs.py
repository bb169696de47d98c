"""The type stubs describe the compiled module: every class, method and property of the
stubs exists, with the same parameter names in the same order."""

import ast
import inspect
from pathlib import Path

import stokesian

STUBS = Path(stokesian.__file__).with_name("_stokesian.pyi")


def signature(f, target):
    """The parameter names of the stub's function ``f`` and of the module's ``target``
    (without ``self``)."""
    stub = [a.arg for a in f.args.args + f.args.kwonlyargs if a.arg != "self"]
    params = [p for p in inspect.signature(target).parameters if p != "self"]
    return stub, params


def test_stubs_match_the_module():
    tree = ast.parse(STUBS.read_text())
    # the classes of the module; the stub's TypedDicts describe the dicts it returns
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef)
               and not any(isinstance(b, ast.Name) and b.id == "TypedDict" for b in n.bases)]
    assert {c.name for c in classes} == {"System", "NBody", "InputError"}
    functions = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
    assert {f.name for f in functions} == {"confinements"}
    for f in functions:
        stub, params = signature(f, getattr(stokesian, f.name))
        assert params == stub, f"{f.name}: module {params}, stub {stub}"
    checked = 0
    for cls in classes:
        runtime = getattr(stokesian, cls.name)
        for f in (n for n in cls.body if isinstance(n, ast.FunctionDef)):
            assert hasattr(runtime, f.name), f"{cls.name}.{f.name} missing"
            if any(isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list):
                continue
            target = runtime if f.name == "__init__" else getattr(runtime, f.name)
            stub, params = signature(f, target)
            assert params == stub, f"{cls.name}.{f.name}: module {params}, stub {stub}"
            checked += 1
    assert checked >= 16
    assert (STUBS.parent / "py.typed").exists()
