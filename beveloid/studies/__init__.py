"""Studies over the analyses: the paper reproduction and the loaded study of Figs 24-25 (loaded.py)."""
