"""The exact flow of the vibro-impact model (8): the linear flights' propagators and their
parameter derivatives, the wall crossings and the impact's reset and saltation matrix (eqs. 8,
21), and the corrected impact model's state-dependent wall |w| = D(v) (the band)."""
