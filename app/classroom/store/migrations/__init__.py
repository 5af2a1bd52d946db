"""Alembic's migrations of the course record (``env.py`` and ``versions/``)."""
