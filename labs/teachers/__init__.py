"""The teachers' tools: per-student variants, ``dynlab check``, coursework tables."""
