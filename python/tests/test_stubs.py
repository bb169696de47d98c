"""The type stubs describe the compiled module: every class, method and property of the
stubs exists, with the same parameter names in the same order."""

import ast
import inspect
from pathlib import Path

import stokesian

STUBS = Path(stokesian.__file__).with_name("_stokesian.pyi")


def test_stubs_match_the_module():
    tree = ast.parse(STUBS.read_text())
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef)]
    assert {c.name for c in classes} == {"System", "NBody"}
    checked = 0
    for cls in classes:
        runtime = getattr(stokesian, cls.name)
        for f in (n for n in cls.body if isinstance(n, ast.FunctionDef)):
            assert hasattr(runtime, f.name), f"{cls.name}.{f.name} missing"
            if any(isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list):
                continue
            stub = [a.arg for a in f.args.args + f.args.kwonlyargs][1:]
            target = runtime if f.name == "__init__" else getattr(runtime, f.name)
            params = [p for p in inspect.signature(target).parameters if p != "self"]
            assert params == stub, f"{cls.name}.{f.name}: module {params}, stub {stub}"
            checked += 1
    assert checked >= 16
    assert (STUBS.parent / "py.typed").exists()
