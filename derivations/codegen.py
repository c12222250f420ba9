"""Write sympy expressions as numpy-vectorised Python functions, deterministically.

The output must be byte-for-byte reproducible on any machine with the pinned sympy minor series
(see pyproject.toml): expressions are printed with sympy's NumPyPrinter after common-subexpression
elimination, no floats are introduced (coefficients stay rational), and nothing depends on
dictionary or set order.
"""

from __future__ import annotations

import dataclasses

import sympy as sp
from sympy.printing.numpy import NumPyPrinter

SYMPY_RANGE = ">=1.14,<1.15"


def check_sympy_version():
    """Refuse to write code with a sympy outside the pinned series: the output would differ."""
    major, minor = (int(x) for x in sp.__version__.split(".")[:2])
    if (major, minor) != (1, 14):
        raise RuntimeError(
            f"sympy {sp.__version__} is outside the pinned series {SYMPY_RANGE}; install it from "
            "pyproject.toml"
        )


HEADER = '''\
"""{title}

GENERATED CODE - DO NOT EDIT.
Written by derivations/{script} with sympy {sympy_range} (pinned in pyproject.toml: the printer's
output, including its float spellings such as ``**(-1.0)``, is only reproducible within one series).
Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive --check`
fails when this file is stale. Equations are cited in the hand-written modules that use it.
"""
# fmt: off
# ruff: noqa
import numpy

'''


@dataclasses.dataclass(frozen=True)
class Function:
    """One generated function.

    ``vector_args`` are (name, symbols) pairs unpacked from an array argument (leading axis);
    ``scalar_args`` are symbols passed as they are. ``outputs`` is a sympy Matrix; the function
    returns an array of shape ``outputs.shape + broadcast shape`` of the vector components and
    of the arguments named in ``broadcast`` (a column matrix is returned as a vector, a 1x1
    matrix as an array of the broadcast shape). A kernel (:func:`render_kernels`) writes its
    column into ``out``, or returns it as a tuple where ``returns`` (no array to allocate where a
    compiled caller needs the values only as numbers).
    """

    name: str
    doc: str
    vector_args: tuple
    scalar_args: tuple
    outputs: sp.Matrix
    broadcast: tuple = ("tau",)
    returns: bool = False


class _Printer(NumPyPrinter):
    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "inline": True, "allow_unknown_functions": False})

    def _print_Max(self, expr):
        # Max only guards integer exponents (see models.guard_zero_power): Python's max suffices.
        return f"max({', '.join(self._print(a) for a in expr.args)})"


def _body(fn: Function) -> list[str]:
    printer = _Printer()
    shape = fn.outputs.shape
    flat = list(fn.outputs)
    names = sp.numbered_symbols("x")
    replacements, reduced = sp.cse(flat, symbols=names, optimizations="basic", order="canonical")
    lines = []
    for name, vector in fn.vector_args:
        lines.append(f"    {', '.join(str(s) for s in vector)} = {name}")
    for sym, expr in replacements:
        lines.append(f"    {sym} = {printer.doprint(expr)}")
    varying = [str(s) for _, vector in fn.vector_args for s in vector]
    varying += [str(s) for s in fn.scalar_args if str(s) in fn.broadcast]
    shape_expr = f"numpy.broadcast({', '.join(varying)}).shape" if varying else "()"
    lines.append(f"    shape = {shape_expr}")
    if shape == (1, 1):
        out_shape, targets = "", ["out[...]"]
    elif shape[1] == 1:
        out_shape, targets = f"({shape[0]},) + ", [f"out[{i}]" for i in range(shape[0])]
    else:
        out_shape = f"{shape!r} + "
        targets = [f"out[{i}, {j}]" for i in range(shape[0]) for j in range(shape[1])]
    lines.append(f"    out = numpy.zeros({out_shape}shape)")
    for target, expr in zip(targets, reduced):
        if expr == 0:
            continue
        lines.append(f"    {target} = {printer.doprint(expr)}")
    lines.append("    return out")
    return lines


class _KernelPrinter(_Printer):
    def _print_Pow(self, expr, rational=False):
        # A power with a symbolic exponent (w^(2n+1), w^(2p)) is a whole power: int_power lets the
        # compiled integrator square instead of calling libm's pow (slosh_bif/model/powers.py).
        if expr.exp.free_symbols:
            return f"int_power({self._print(expr.base)}, {self._print(expr.exp)})"
        return super()._print_Pow(expr, rational=rational)


def _kernel_body(fn: Function) -> list[str]:
    """Scalar statements writing ``fn.outputs`` (a column) into ``out`` in place, or returning it
    as a tuple (``fn.returns``)."""
    printer = _KernelPrinter()
    replacements, reduced = sp.cse(
        list(fn.outputs), symbols=sp.numbered_symbols("x"), optimizations="basic", order="canonical"
    )
    lines = [f"    {s} = pars[{i}]" for i, s in enumerate(fn.scalar_args)]
    for name, vector in fn.vector_args:
        lines += [f"    {s} = {name}[{i}]" for i, s in enumerate(vector)]
    lines += [f"    {sym} = {printer.doprint(expr)}" for sym, expr in replacements]
    if fn.returns:
        # numbers as floats: one element type, so that a compiled caller may index the tuple
        items = [repr(float(e)) if e.is_Number else printer.doprint(e) for e in reduced]
        return lines + ["    return ("] + [f"        {item}," for item in items] + ["    )"]
    lines += [f"    out[{i}] = {printer.doprint(expr)}" for i, expr in enumerate(reduced)]
    return lines


def render_kernels(title: str, script: str, functions: list[Function], constants: tuple = ()) -> str:
    """Source text of scalar, allocation-free kernels ``name(tau, <vector args>, out, pars)``
    (``name(tau, <vector args>, pars)`` returning a tuple where ``fn.returns``).

    Every output component is written (zeros included) so that ``out`` may be uninitialised;
    ``pars`` holds ``fn.scalar_args`` in order. Plain Python that numba compiles unchanged.
    ``constants``: (name, comment, tuple) written after the functions.
    """
    text = HEADER.format(title=title, script=script, sympy_range=SYMPY_RANGE)
    text += "from slosh_bif.model.powers import int_power\n\n"
    for fn in functions:
        args = ["tau"] + [name for name, _ in fn.vector_args] + ([] if fn.returns else ["out"]) + ["pars"]
        text += f"\ndef {fn.name}({', '.join(args)}):\n"
        text += f'    """{fn.doc}"""\n'
        text += "\n".join(_kernel_body(fn)) + "\n\n"
    for name, comment, value in constants:
        text += f"\n# {comment}\n{name} = {value!r}\n"
    return text.rstrip("\n") + "\n"


def render_module(title: str, script: str, functions: list[Function]) -> str:
    """Source text of a module holding ``functions``."""
    text = HEADER.format(title=title, script=script, sympy_range=SYMPY_RANGE)
    for fn in functions:
        scalars = [str(s) for s in fn.scalar_args]
        time = [name for name in scalars if name == "tau"]  # tau first, as in scipy's fun(t, y)
        args = time + [name for name, _ in fn.vector_args] + [name for name in scalars if name != "tau"]
        text += f"\ndef {fn.name}({', '.join(args)}):\n"
        text += f'    """{fn.doc}"""\n'
        text += "\n".join(_body(fn)) + "\n\n"
    return text.rstrip("\n") + "\n"
