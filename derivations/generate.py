"""Regenerate every generated module of slosh_bif (and, with --check, verify they are fresh).

Usage:  python derivations/generate.py [--check] [--out DIR]
        slosh-bif derive [--check]

Each derivation module builds sympy expressions; this script turns them into numpy code under
``slosh_bif/model/_generated/`` and writes ``derivations/REPORT.md`` (printed against derived equations).
``--check`` renders into memory and compares byte for byte with the committed files, exiting 1
(and naming the stale files) when they differ. ``--out`` names another root to write or check.
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

import codegen  # noqa: E402
import impact_reset  # noqa: E402
import models as m  # noqa: E402
import numpy as np  # noqa: E402
import report  # noqa: E402
import slow_flow  # noqa: E402
import sympy as sp  # noqa: E402

ROOT = HERE.parent
GENERATED = Path("slosh_bif") / "model" / "_generated"
SCRIPT = "generate.py"


def _models_module() -> str:
    m.check_energy_balances()
    phi = sp_matrix(sp.symbols("phi0:16", real=True)).reshape(4, 4)
    variational = sp_matrix(list(m.smooth_rhs()) + list(m.jacobian(m.smooth_rhs()) * phi))
    state = (("y", m.STATE),)
    full = (m.tau,) + m.PARAMS
    F = codegen.Function
    smooth = m.smooth_rhs()
    impact = m.impact_rhs()
    # Model (8) between impacts is y' = M y + F cos(tau): read M and F off the right-hand side.
    impact_matrix = impact.jacobian(sp_matrix(m.STATE))
    impact_forcing = impact.diff(m.Abar).subs(m.tau, 0) * m.Abar
    linear = m.LINEAR_PARAMS + (m.Abar,)

    def derivatives(M):
        """[dM/dq | dF/dq] for q in eps, beta, gamma, sigma, Abar, stacked (20 x 5): the propagators'
        parameter derivatives need dK/dq exactly (no differences)."""
        block = M.row_join(impact_forcing)
        return sp.Matrix.vstack(*(block.diff(q) for q in linear))

    dirs = tuple(tuple(sp.symbols(f"{name}0:4", real=True)) for name in ("a", "b", "c"))
    functions = [
        F("smooth_rhs", "Right-hand side of the smooth model (9); y = [X, X', w, w'].", state, full, smooth),
        F(
            "smooth_second",
            "Second derivative of (9)'s right-hand side along a and b, f_yy[a, b] (the wall's terms).",
            state + (("a", dirs[0]), ("b", dirs[1])),
            full,
            m.directional(smooth, dirs[0], dirs[1]),
        ),
        F(
            "smooth_third",
            "Third derivative of (9)'s right-hand side along a, b and c, f_yyy[a, b, c].",
            state + (("a", dirs[0]), ("b", dirs[1]), ("c", dirs[2])),
            full,
            m.directional(smooth, *dirs),
        ),
        F(
            "smooth_jac",
            "Jacobian d(rhs)/dy of the smooth model (9), shape (4, 4, ...).",
            state,
            full,
            m.jacobian(smooth),
        ),
        F(
            "smooth_variational",
            "Variational equations of (9): d/dtau [y, Phi] = [f(y), J(y) Phi], Phi row-major (16,).",
            state + (("Phi", tuple(phi)),),
            full,
            variational,
        ),
        F(
            "smooth_energy",
            "Energy H of the smooth model (9).",
            state,
            m.PARAMS,
            sp_matrix([m.smooth_energy()]),
        ),
        F(
            "smooth_power",
            "dH/dtau of the smooth model (9) along solutions.",
            state,
            full,
            sp_matrix([m.smooth_power()]),
        ),
        F(
            "impact_matrix",
            "Matrix M of the linear flow y' = M y + F cos(tau) of model (8).",
            (),
            m.LINEAR_PARAMS,
            impact_matrix,
        ),
        F(
            "flight_matrix",
            "Matrix M of (9) without the wall (lam = chi = 0): the flights of the corrected impact model.",
            (),
            m.LINEAR_PARAMS,
            m.flight_rhs().jacobian(sp_matrix(m.STATE)),
        ),
        F(
            "impact_linear_derivatives",
            "[dM/dq | dF/dq] of model (8) for q = eps, beta, gamma, sigma, Abar, stacked (20 x 5).",
            (),
            linear,
            derivatives(impact_matrix),
        ),
        F(
            "flight_linear_derivatives",
            "[dM/dq | dF/dq] of (9)'s flights for q = eps, beta, gamma, sigma, Abar, stacked (20 x 5).",
            (),
            linear,
            derivatives(m.flight_rhs().jacobian(sp_matrix(m.STATE))),
        ),
        F(
            "impact_forcing",
            "Forcing vector F of the linear flow of model (8).",
            (),
            (m.eps, m.Abar),
            impact_forcing,
        ),
        F(
            "impact_weight",
            "Weight mu of the w-row in the energy of model (8).",
            (),
            (m.eps, m.beta, m.sigma),
            sp_matrix([m.impact_weight()]),
        ),
        F(
            "impact_energy",
            "Energy H of model (8) between impacts.",
            state,
            m.LINEAR_PARAMS,
            sp_matrix([m.impact_energy()]),
        ),
        F(
            "impact_power",
            "dH/dtau of model (8) between impacts.",
            state,
            (m.tau,) + m.LINEAR_PARAMS + (m.Abar,),
            sp_matrix([m.impact_power()]),
        ),
    ]
    return codegen.render_module(
        "Right-hand sides, Jacobians and energies of models (8) and (9).", SCRIPT, functions
    )


def _kernels_module() -> str:
    """Kernels for the compiled integrator: (9) alone, and (9) with everything shooting needs.

    The shooting state is z = [y (4), Phi (16, row-major), dy/dsigma (4), dy/dAbar (4), int tr J]:
    the orbit, its monodromy, its sensitivities to the two continued parameters and the
    Liouville integral, all from one integration. The *pair* kernel has the same state with the
    two sensitivities taken along any two directions in the real parameters (eps, beta, gamma,
    sigma, Abar, lam, chi): its ``pars`` carry the two directions' weights after the parameters,
    so one compiled kernel serves every pair of a two-parameter curve (a kernel per pair would be
    21 kernels; 49 components with all seven sensitivities would cost every curve 70 % more).
    """
    f = m.smooth_rhs()
    J = m.jacobian(f)
    phi = sp_matrix(sp.symbols("phi0:16", real=True)).reshape(4, 4)
    s_sigma = sp_matrix(sp.symbols("s0:4", real=True))
    s_abar = sp_matrix(sp.symbols("q0:4", real=True))
    shooting = sp_matrix(
        list(f)
        + list(J * phi)
        + list(J * s_sigma + f.diff(m.sigma))
        + list(J * s_abar + f.diff(m.Abar))
        + [J.trace()]
    )
    weights = [sp.symbols(f"{slot}_{q}", real=True) for slot in ("a", "b") for q in m.REAL_PARAMS]
    slot_a, slot_b = weights[: len(m.REAL_PARAMS)], weights[len(m.REAL_PARAMS) :]
    forced = [
        sum((c * f.diff(q) for c, q in zip(slot, m.REAL_PARAMS)), sp.zeros(4, 1)) for slot in (slot_a, slot_b)
    ]
    pair = sp_matrix(
        list(f) + list(J * phi) + list(J * s_sigma + forced[0]) + list(J * s_abar + forced[1]) + [J.trace()]
    )
    state = (("y", m.STATE),)
    augmented = (("z", tuple(m.STATE) + tuple(phi) + tuple(s_sigma) + tuple(s_abar) + (sp.Symbol("trace"),)),)
    # the map's derivatives along any directions (flows/smooth/variations.py, orbits/map_derivatives.py):
    # f, J and the non-zero entries of f's second and third derivatives in the state, the
    # variational equations of every order contracted from them by one hand-written kernel
    second, third = _derivative_entries(f)
    # the arcs' derivatives along a direction d of the start state (the curve problems' second
    # derivatives, orbits/codim2/minaug.py): d' = J d, Psi = D Phi . d, r = D (dy/da, dy/db) . d
    d = sp_matrix(sp.symbols("d0:4", real=True))
    psi = sp_matrix(sp.symbols("psi0:16", real=True)).reshape(4, 4)
    r_a, r_b = (sp_matrix(sp.symbols(f"{name}0:4", real=True)) for name in ("ra", "rb"))
    H = m.directional(f, d).jacobian(sp.Matrix(m.STATE)).applyfunc(m.guard_negative_powers)  # f_yy[d, .]
    along = sp_matrix(
        list(pair)
        + list(J * d)
        + list(J * psi + H * phi)
        + list(J * r_a + H * s_sigma + m.directional(forced[0], d))
        + list(J * r_b + H * s_abar + m.directional(forced[1], d))
    )
    along_state = (("z", augmented[0][1] + tuple(d) + tuple(psi) + tuple(r_a) + tuple(r_b)),)
    # the same 28 for the (sigma, Abar) pair of the dedicated shooting kernel (no weights to carry)
    along_sigma_abar = sp_matrix(
        list(J * d)
        + list(J * psi + H * phi)
        + list(J * r_a + H * s_sigma + m.directional(f.diff(m.sigma), d))
        + list(J * r_b + H * s_abar + m.directional(f.diff(m.Abar), d))
    )
    F = codegen.Function
    return codegen.render_kernels(
        "Scalar kernels of the smooth model (9) for the compiled integrator "
        "(slosh_bif.flows.smooth.integrator).",
        SCRIPT,
        [
            F(
                "smooth_rhs_kernel",
                "out = f(tau, y) of (9); pars = (eps, beta, gamma, sigma, Abar, lam, chi, n, p).",
                state,
                m.PARAMS,
                f,
            ),
            F(
                "smooth_shooting_kernel",
                "out = d/dtau [y, Phi, dy/dsigma, dy/dAbar, int tr J] for (9), 29 components.",
                augmented,
                m.PARAMS,
                shooting,
            ),
            F(
                "smooth_pair_kernel",
                "out = d/dtau [y, Phi, dy/da, dy/db, int tr J] for (9), 29 components; a and b are "
                "the directions "
                "pars[9:16] and pars[16:23] in (eps, beta, gamma, sigma, Abar, lam, chi).",
                augmented,
                m.PARAMS + tuple(slot_a) + tuple(slot_b),
                pair,
            ),
            F(
                "smooth_along_kernel",
                "out = d/dtau [y, Phi, dy/da, dy/db, int tr J, dy/dy0 . d, D Phi . d, D dy/da . d, "
                "D dy/db . d] for (9), 57 components: the pair kernel's 29 and their derivatives along "
                "the start state's direction d (the second-order variational equations; a and b as for "
                "the pair kernel).",
                along_state,
                m.PARAMS + tuple(slot_a) + tuple(slot_b),
                along,
            ),
            F(
                "smooth_along_extra_kernel",
                "out = the along kernel's components 29 to 56 alone (28): d/dtau [dy/dy0 . d, D Phi . d, "
                "D dy/da . d, D dy/db . d], replayed on the steps of a recorded integration of the first 29.",
                along_state,
                m.PARAMS + tuple(slot_a) + tuple(slot_b),
                sp_matrix(list(along)[29:]),
            ),
            F(
                "smooth_along_sigma_abar_kernel",
                "out = the along extra kernel's 28 components for the (sigma, Abar) pair of the "
                "shooting kernel (a = sigma, b = Abar), replayed on the steps of its integration.",
                along_state,
                m.PARAMS,
                along_sigma_abar,
            ),
            F(
                "smooth_jet_kernel",
                "(f, J row-major, f_yy[i, j, k], f_yyy[i, j, k, l]) of (9) at (tau, y): the right-hand "
                "side, its Jacobian and the non-zero entries of its second and third derivatives in "
                "the state, in the order of SMOOTH_SECOND_ENTRIES and SMOOTH_THIRD_ENTRIES.",
                state,
                m.PARAMS,
                sp_matrix(list(f) + list(J) + list(second.values()) + list(third.values())),
                returns=True,
            ),
        ],
        constants=(
            ("SMOOTH_SECOND_ENTRIES", "(i, j, k) of each non-zero d2 f_i / dy_j dy_k", tuple(second)),
            ("SMOOTH_THIRD_ENTRIES", "(i, j, k, l) of each non-zero d3 f_i / dy_j dy_k dy_l", tuple(third)),
        ),
    )


def _derivative_entries(f):
    """({(i, j, k): d2 f_i / dy_j dy_k}, {(i, j, k, l): d3 f_i / dy_j dy_k dy_l}), the non-zero
    entries of the second and third derivatives of ``f`` in the state (every order of the indices
    listed: the contractions need no symmetry bookkeeping)."""
    y = m.STATE
    second, third = {}, {}
    for i, j, k in itertools.product(range(len(y)), repeat=3):
        entry = m.guard_negative_powers(f[i].diff(y[j], y[k]))
        if entry != 0:
            second[(i, j, k)] = entry
        for r in range(len(y)):
            entry = m.guard_negative_powers(f[i].diff(y[j], y[k], y[r]))
            if entry != 0:
                third[(i, j, k, r)] = entry
    return second, third


def _tableau_module() -> str:
    """The DOP853 coefficients the compiled loop uses, written from scipy's own (exact float reprs), so
    that the loop neither imports scipy.integrate (a third of a second at start-up) nor differs
    from scipy's method by a digit."""
    from scipy.integrate._ivp import dop853_coefficients as dop

    stages = dop.N_STAGES

    def rows(name, array):
        array = np.asarray(array, dtype=float)
        if array.ndim == 1:
            return f"{name} = ({', '.join(repr(float(v)) for v in array)},)\n"
        inner = "".join(f"    ({', '.join(repr(float(v)) for v in row)},),\n" for row in array)
        return f"{name} = (\n{inner})\n"

    return (
        '"""The coefficients of DOP853 (Hairer, Norsett & Wanner) as scipy\'s solve_ivp has them.\n\n'
        "GENERATED CODE - DO NOT EDIT.\n"
        f"Written by derivations/{SCRIPT} from scipy.integrate._ivp.dop853_coefficients.\n"
        "Regenerate with `slosh-bif derive` (or `python derivations/generate.py`); `slosh-bif derive "
        '--check`\nfails when this file is stale.\n"""\n\n'
        f"N_STAGES = {stages}\n"
        + rows("A", dop.A[:stages, :stages])
        + rows("B", dop.B)
        + rows("C", dop.C[:stages])
        + rows("E3", dop.E3)
        + rows("E5", dop.E5)
    )


def sp_matrix(items):
    return sp.Matrix(list(items))


def render_all() -> dict[Path, str]:
    """Path (relative to the repository root) -> text of every generated file."""
    return {
        GENERATED
        / "__init__.py": '"""Generated code: written by derivations/generate.py, never edited by hand."""\n',
        GENERATED / "models.py": _models_module(),
        GENERATED / "kernels.py": _kernels_module(),
        GENERATED / "dop853_tableau.py": _tableau_module(),
        GENERATED / "impact_kernels.py": codegen.render_kernels(
            "The impact of the vibro-impact model (8): its reset and saltation matrix, for the compiled "
            "flow (slosh_bif.flows.impact.flow).",
            SCRIPT,
            impact_reset.kernel_functions(codegen.Function),
        ),
        GENERATED / "slow_flow.py": codegen.render_module(
            "The slow invariant manifold (36), slow flow (45), steady states (46) and kappa on the "
            "manifold (39).",
            SCRIPT,
            slow_flow.generated_functions(codegen.Function) + slow_flow.corrected_functions(codegen.Function),
        ),
        Path("derivations") / "REPORT.md": report.render(),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "--check", action="store_true", help="exit 1 if the committed generated code is stale"
    )
    parser.add_argument(
        "--out", type=Path, default=ROOT, help="repository root to write or check (default: this checkout)"
    )
    args = parser.parse_args(argv)
    codegen.check_sympy_version()
    rendered = render_all()
    if args.check:
        stale = [
            str(path)
            for path, text in rendered.items()
            if not (args.out / path).is_file() or (args.out / path).read_text() != text
        ]
        if stale:
            print(
                f"stale generated code under {args.out}: {', '.join(stale)}; run `slosh-bif derive`",
                file=sys.stderr,
            )
            return 1
        print(f"generated code under {args.out} is fresh ({len(rendered)} files)")
        return 0
    for path, text in rendered.items():
        (args.out / path).parent.mkdir(parents=True, exist_ok=True)
        (args.out / path).write_text(text)
    print(f"wrote {len(rendered)} files under {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
