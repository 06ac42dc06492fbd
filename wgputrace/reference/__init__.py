"""Our scenes in other renderers, for references and comparisons (optional extra: `wgputrace[reference]`).

Nothing here imports a reference renderer at import time: callers pass the loaded module in.
"""
