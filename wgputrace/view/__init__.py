"""The viewer's GPU side, above render and below app: progressive bands of rows within a frame
budget (`BandedRenderer`), the guides, filter and resolve passes (`Display`), presenting to a
window (`Presenter`), and their structs and bind groups (view.layout)."""
