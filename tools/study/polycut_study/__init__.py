"""polycut-study: trade studies of polycut's methods (docs/study.md)."""
