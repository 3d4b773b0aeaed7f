"""dynlab's lab works: one module per lab of the manual (and its report), the coursework, and
the registry that finds them; the command line, the teachers' tools and the lab benchmarks are
subpackages."""
