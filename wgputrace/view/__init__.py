"""The viewer's GPU side, above render and below app: progressive bands of rows within a frame
budget (banded.py), the guides, filter and resolve passes (display.py), presenting to a window
(present.py), and their structs and bind groups (layout.py)."""
