"""Computer vision (OpenCV): paper oscillograms and torsiograms read off photographs and scans."""
from .record import PaperRecord, read_paper_record, read_paper_records

__all__ = ["PaperRecord", "read_paper_record", "read_paper_records"]
