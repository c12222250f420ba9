"""The outputs of a wall fit (:mod:`.impact_records`): ``fit.json`` (estimates, intervals, the
profile over pbar, the data file's SHA-256), ``fit.png`` (the records with the fitted law (21) and
the residuals) and ``params.toml``, the fitted parameter set that every command takes with
``--params``."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

from slosh_bif.atomic import write_text_atomically
from slosh_bif.model import restitution
from slosh_bif.model.parameter_file import render_parameter_file
from slosh_bif.model.params import Params

__all__ = ["write_fit"]


def write_fit(fit, records, base: Params, folder) -> list:
    """Write fit.json, fit.png and params.toml into ``folder``; returns their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    record = fit.as_dict()
    if records.source:
        record["data"] = {
            "file": records.source,
            "sha256": hashlib.sha256(Path(records.source).read_bytes()).hexdigest(),
        }
    paths = [write_text_atomically(folder / "fit.json", json.dumps(record, indent=2) + "\n")]
    paths.append(
        write_text_atomically(
            folder / "params.toml",
            render_parameter_file(
                params=fit.params(base),
                comment="the wall fitted by `slosh-bif fit` (eq. 21) to "
                + (records.source or "impact records"),
            ),
        )
    )
    paths.append(_plot(fit, records, folder / "fit.png"))
    return paths


def _plot(fit, records, path) -> Path:
    from slosh_bif.report.plotting import pyplot, save_figure

    plt = pyplot()
    fig, (top, bottom) = plt.subplots(
        2, 1, figsize=(7, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    v = np.geomspace(records.v0.min(), records.v0.max(), 200)
    values = fit.values
    law = restitution.kappa(v, values["lam"], values["chi"], values["n"], values["pbar"])
    at_data = restitution.kappa(records.v0, values["lam"], values["chi"], values["n"], values["pbar"])
    yerr = records.std / records.v0 if records.std is not None else None
    top.errorbar(records.v0, records.kappa, yerr=yerr, fmt="o", ms=4, color="k", label="records: v_out / v0")
    top.plot(
        v,
        law,
        "-",
        color="tab:red",
        label=f"eq. (21): n = {values['n']}, pbar = {values['pbar']}, C = {fit.C:.4g} +- "
        f"{1.96 * fit.C_std:.2g}",
    )
    top.set_ylabel("restitution kappa")
    top.legend(fontsize=8)
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.plot(records.v0, records.kappa - at_data, "o", ms=3, color="k")
    bottom.set_xlabel("impact speed v0")
    bottom.set_ylabel("residual")
    top.set_title("the wall's restitution law fitted to impact records", fontsize=10)
    return save_figure(fig, path)
