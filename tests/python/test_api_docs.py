"""`help()` shows what the type stubs (python/traxer.pyi) show: the same public
names on every class and in the module, the same parameters with the same
(real) defaults, and a docstring at run time wherever the stub has one, opening
with the stub's first sentence. The stub is parsed with `ast`, not imported, so
the two are compared as written.
"""

import ast
import inspect
import pathlib
import re

import pytest

import traxer

STUB = pathlib.Path(__file__).resolve().parents[2] / "python" / "traxer.pyi"
TREE = ast.parse(STUB.read_text())


def stub_classes():
    return {n.name: n for n in TREE.body if isinstance(n, ast.ClassDef)}


def stub_functions(body):
    return {n.name: n for n in body if isinstance(n, ast.FunctionDef)}


def stub_attributes(body):
    """Annotated attributes and their docstrings (the string after them)."""
    out = {}
    for i, n in enumerate(body):
        if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name):
            nxt = body[i + 1] if i + 1 < len(body) else None
            doc = (
                nxt.value.value
                if isinstance(nxt, ast.Expr) and isinstance(nxt.value, ast.Constant)
                else None
            )
            out[n.target.id] = doc
    return out


def first_sentence(text):
    """The first sentence, with backticks, quotes' doubling and spacing
    normalised (the stub writes ``x`` where Rust docs write `x`)."""
    t = " ".join(text.replace("``", "`").replace("`", "").split())
    m = re.match(r"(.+?[.:;])(\s|$)", t)
    return (m.group(1) if m else t).rstrip(".:;")


def normalised(text):
    return " ".join(text.replace("``", "`").replace("`", "").split())


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_params(fn):
    """[(name, default source or None)] without self."""
    args = fn.args
    names = [a.arg for a in args.posonlyargs + args.args]
    defaults = [None] * (len(names) - len(args.defaults)) + [
        ast.unparse(d) for d in args.defaults
    ]
    return [(n, d) for n, d in zip(names, defaults) if n != "self"]


def runtime_params(obj):
    out = []
    for p in inspect.signature(obj).parameters.values():
        if p.name == "self":
            continue
        d = None if p.default is inspect.Parameter.empty else repr(p.default)
        out.append((p.name, d))
    return out


def same_default(stub, runtime):
    if stub is None or runtime is None:
        return stub == runtime
    try:
        return ast.literal_eval(stub) == ast.literal_eval(runtime)
    except ValueError:
        return stub == runtime


CLASSES = sorted(stub_classes())


def test_the_stub_has_every_public_name_of_the_module_and_no_other():
    stub = public(stub_classes()) | public(stub_functions(TREE.body))
    stub |= {
        n.target.id
        for n in TREE.body
        if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
    }
    stub = public(stub)
    # `traxer.traxer` is the compiled extension the package re-exports.
    runtime = public(dir(traxer)) - {"traxer"}
    assert runtime - stub == set(), "in the module, not in traxer.pyi"
    assert stub - runtime == set(), "in traxer.pyi, not in the module"


@pytest.mark.parametrize("cls", CLASSES)
def test_each_class_has_the_stubs_names(cls):
    node = stub_classes()[cls]
    stub = public(stub_functions(node.body)) | public(stub_attributes(node.body))
    runtime_cls = getattr(traxer, cls)
    base = set(dir(ValueError)) if issubclass(runtime_cls, BaseException) else set()
    if issubclass(runtime_cls, BaseException):
        # Exception attributes are set on each instance, not the class.
        assert stub - public(dir(runtime_cls)) <= {"file", "line", "key", "message"}
        return
    runtime = public(set(dir(runtime_cls)) - base)
    assert runtime - stub == set(), f"{cls}: at run time, not in the stub"
    assert stub - runtime == set(), f"{cls}: in the stub, not at run time"


def callables():
    out = []
    for name, fn in stub_functions(TREE.body).items():
        out.append((name, fn, getattr(traxer, name)))
    for cls, node in stub_classes().items():
        for name, fn in stub_functions(node.body).items():
            if name.startswith("_") and name != "__init__":
                continue
            target = getattr(traxer, cls) if name == "__init__" else getattr(getattr(traxer, cls), name)
            out.append((f"{cls}.{name}", fn, target))
    return out


@pytest.mark.parametrize("name,fn,target", callables(), ids=[c[0] for c in callables()])
def test_signatures_and_real_defaults_agree(name, fn, target):
    if any(isinstance(d, ast.Attribute) and getattr(d, "attr", "") == "setter" for d in fn.decorator_list):
        return
    if any(isinstance(d, ast.Name) and d.id == "property" for d in fn.decorator_list):
        return
    stub = stub_params(fn)
    assert all(d != "..." for _, d in stub), f"{name}: the stub hides a default as ..."
    runtime = runtime_params(target)
    assert [n for n, _ in stub] == [n for n, _ in runtime], name
    for (n, a), (_, b) in zip(stub, runtime):
        assert same_default(a, b), f"{name}({n}=...): stub {a}, help() {b}"


def documented():
    """(label, stub docstring, runtime docstring) of everything the stub documents."""
    out = []
    for name, fn in stub_functions(TREE.body).items():
        doc = ast.get_docstring(fn)
        if doc:
            out.append((name, doc, getattr(traxer, name).__doc__))
    for cls, node in stub_classes().items():
        runtime_cls = getattr(traxer, cls)
        doc = ast.get_docstring(node)
        if doc:
            out.append((cls, doc, runtime_cls.__doc__))
        if issubclass(runtime_cls, BaseException):
            continue
        for name, fn in stub_functions(node.body).items():
            doc = ast.get_docstring(fn)
            if doc and name != "__init__":
                out.append((f"{cls}.{name}", doc, getattr(runtime_cls, name).__doc__))
        for name, doc in stub_attributes(node.body).items():
            if doc:
                out.append((f"{cls}.{name}", doc, getattr(runtime_cls, name).__doc__))
    return out


@pytest.mark.parametrize("label,stub,runtime", documented(), ids=[d[0] for d in documented()])
def test_help_shows_the_stubs_docstring(label, stub, runtime):
    assert runtime, f"{label}: documented in traxer.pyi, no docstring at run time"
    assert first_sentence(stub) in normalised(runtime), (
        f"{label}: help() does not say the stub's first sentence\n"
        f"  stub:    {first_sentence(stub)}\n  runtime: {normalised(runtime)[:200]}"
    )


def test_every_public_attribute_has_a_docstring_in_the_stub():
    missing = []
    for cls, node in stub_classes().items():
        if issubclass(getattr(traxer, cls), BaseException):
            continue
        for name, doc in stub_attributes(node.body).items():
            if not name.startswith("_") and not doc:
                missing.append(f"{cls}.{name}")
        for name, fn in stub_functions(node.body).items():
            if not name.startswith("_") and not ast.get_docstring(fn):
                missing.append(f"{cls}.{name}()")
    assert missing == []


def test_scene_error_documents_its_attributes():
    doc = traxer.SceneError.__doc__
    for attribute in ["file", "line", "key", "message"]:
        assert attribute in doc
