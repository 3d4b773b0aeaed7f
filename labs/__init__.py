"""dynlab's lab works: one module per lab of the manual, plus the command line."""
