"""The files a lab reads and writes: recordings, typed tables, TOML, record checks."""
