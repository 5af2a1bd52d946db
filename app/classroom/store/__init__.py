"""The course record: classes, students and every attempt, kept in a database
(SQLite by default, PostgreSQL for several machines) through SQLAlchemy Core, its
schema built and upgraded by Alembic migrations."""
