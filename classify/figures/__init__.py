"""Figures (matplotlib, drawn on :class:`matplotlib.figure.Figure` objects, no pyplot, no display).

One module per kind of picture. Matplotlib is imported inside the functions
that draw, never at the command's start-up.
"""
