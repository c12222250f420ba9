"""Generated code: written by derivations/generate.py, never edited by hand."""
