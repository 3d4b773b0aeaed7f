"""The valve train: its chain of springs, and the forces read off a running drive."""
