"""The central views of the main window; each takes plain arrays or plotdata records, never files."""
