"""Judging a student's reported values, and naming the slip behind a wrong one."""
