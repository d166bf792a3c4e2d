"""Layer 3: the command-line programs. Each module parses, validates, calls the
algorithms and writes; none of them computes on pixels itself."""
