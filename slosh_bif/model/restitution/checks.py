"""The one check every law makes of the parameter set it is given."""

__all__ = ["check_params"]


def check_params(params) -> None:
    """A TypeError unless ``params`` is a parameter set (a :class:`~slosh_bif.model.params.Params`)."""
    if not all(hasattr(params, name) for name in ("lam", "chi", "n", "pbar", "as_dict")):
        raise TypeError(f"params must be a slosh_bif.Params; got {type(params).__name__}")
