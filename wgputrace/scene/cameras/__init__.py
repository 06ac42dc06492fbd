"""Every camera kind, one module each (`Sensor` says what a kind declares), each exported from this
package, from wgputrace.scene and from wgputrace under its class name: `Camera` (the pinhole),
`ThinLensCamera`, `OrthographicCamera` and `EquirectangularCamera`."""

from .sensor import CAMERA_KINDS, CameraError, CameraWarning, Sensor, camera_class, camera_classes

KINDS = CAMERA_KINDS.import_package(__name__, __path__)
globals().update(KINDS)

__all__ = ["CameraError", "CameraWarning", "Sensor", "camera_class", "camera_classes", *KINDS]
