"""The type stubs (tricell/_tricell.pyi) against the compiled module: the same names, and for
every function and method the same parameters with the same defaults as pybind11's signature
(the first line of its docstring); every public name has a docstring, so help() explains it."""
import ast
import inspect
import os

import pytest

import tricell
from tricell import _tricell

STUB = os.path.join(os.path.dirname(tricell.__file__), "_tricell.pyi")


def split_top_level(text):
    """Splits "a: int = 1, b: List[str] = None" at the commas outside brackets and quotes."""
    parts, depth, quote, current = [], 0, None, ""
    for char in text:
        if quote:
            quote = None if char == quote else quote
        elif char in "'\"":
            quote = char
        elif char in "([{":
            depth += 1
        elif char in ")]}":
            depth -= 1
        elif char == "," and depth == 0:
            parts.append(current.strip())
            current = ""
            continue
        current += char
    if current.strip():
        parts.append(current.strip())
    return parts


def native_parameters(function, name):
    """[(parameter, default or inspect.Parameter.empty)] from pybind11's signature line."""
    line = function.__doc__.strip().splitlines()[0]
    assert line.startswith(name + "("), f"{name}: no signature line in {line!r}"
    inside = line[len(name) + 1:line.rindex(") ->")]
    parameters = []
    for part in split_top_level(inside):
        head, _, default = part.partition(" = ")
        parameter = head.split(":")[0].strip()
        value = ast.literal_eval(default) if default else inspect.Parameter.empty
        parameters.append((parameter, value))
    return parameters


def stub_parameters(node):
    args = node.args.args
    defaults = [inspect.Parameter.empty] * (len(args) - len(node.args.defaults))
    defaults += [ast.literal_eval(d) for d in node.args.defaults]
    parameters = [(a.arg, d) for a, d in zip(args, defaults)]
    if node.args.kwonlyargs:  # pybind11's signature line marks them with a bare "*" too
        parameters.append(("*", inspect.Parameter.empty))
        parameters += [(a.arg, inspect.Parameter.empty if d is None else ast.literal_eval(d))
                       for a, d in zip(node.args.kwonlyargs, node.args.kw_defaults)]
    return parameters


def stub_tree():
    with open(STUB) as f:
        return ast.parse(f.read())


def stub_members(class_node):
    methods, properties = {}, set()
    for node in class_node.body:
        if isinstance(node, ast.FunctionDef):
            if any(isinstance(d, ast.Name) and d.id == "property" for d in node.decorator_list):
                properties.add(node.name)
            else:
                methods[node.name] = node
    return methods, properties


def native_names():
    return {n for n in dir(_tricell) if not n.startswith("__")} | {"__version__"}


def test_the_stub_names_every_native_name_and_no_other():
    tree = stub_tree()
    stubbed = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    stubbed |= {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    assert stubbed == native_names()


def test_functions_have_the_native_parameters_and_defaults():
    functions = [n for n in stub_tree().body if isinstance(n, ast.FunctionDef)]
    assert functions
    for node in functions:
        assert stub_parameters(node) == native_parameters(getattr(_tricell, node.name), node.name)


@pytest.mark.parametrize("name", ["NeighborList", "VerletList", "DisplacementTracker", "Rdf"])
def test_classes_have_the_native_methods_properties_and_parameters(name):
    class_node = next(n for n in stub_tree().body if isinstance(n, ast.ClassDef) and n.name == name)
    methods, properties = stub_members(class_node)
    native = getattr(_tricell, name)
    native_methods = {n for n, v in vars(native).items()
                      if (not n.startswith("_") or n == "__init__") and not isinstance(v, property)}
    native_properties = {n for n, v in vars(native).items() if isinstance(v, property)}
    assert set(methods) == native_methods
    assert properties == native_properties
    for method, node in methods.items():
        expected = native_parameters(getattr(native, method), method)
        assert stub_parameters(node) == [("self", inspect.Parameter.empty)] + expected[1:], method


def test_every_public_name_explains_itself_from_inside_the_package():
    docs = {}
    for name in native_names() - {"__version__"}:
        value = getattr(_tricell, name)
        docs[name] = value.__doc__ or ""
        if inspect.isclass(value):
            for member, attribute in vars(value).items():
                if not member.startswith("_") or member == "__init__":
                    docs[f"{name}.{member}"] = attribute.__doc__ or ""
    for name, doc in docs.items():
        assert len(doc.strip()) > 10, f"{name} has no docstring to speak of: {doc!r}"
        for pointer in (".hpp", ".cpp", "include/", "docs/", "http"):
            assert pointer not in doc, f"{name}'s docstring points outside the package: {pointer}"


def test_the_package_is_typed():
    assert os.path.isfile(os.path.join(os.path.dirname(tricell.__file__), "py.typed"))
    assert tricell.__version__.count(".") == 2
