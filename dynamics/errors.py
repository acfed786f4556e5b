"""The one exception type of dynamics/: a scene that breaks a rule."""


class SceneError(ValueError):
    """A scene entry that is not valid; the message names the entry and value."""
