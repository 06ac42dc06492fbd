"""The error every Scene API call raises for bad input (a ValueError, so callers may catch either)."""


class SceneError(ValueError):
    """The scene or a shape cannot be rendered as it is: empty, inconsistent, NaN or infinite geometry."""
