"""The tables of the course record (SQLAlchemy Core); the migrations build the same."""

from __future__ import annotations

import sqlalchemy as sa

metadata = sa.MetaData()

classes = sa.Table(
    "classes",
    metadata,
    sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
    sa.Column("name", sa.String(80), nullable=False, unique=True),
    sa.Column("join_code", sa.String(40), nullable=False),
    sa.Column("join_code_expires", sa.Float, nullable=True),  # epoch seconds; None: never
    sa.Column("closed", sa.Boolean, nullable=False, default=False),
    sa.Column("created", sa.Float, nullable=False),
)

students = sa.Table(
    "students",
    metadata,
    sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
    sa.Column("class_id", sa.Integer, sa.ForeignKey("classes.id"), nullable=False),
    sa.Column("roster_id", sa.String(80), nullable=False, default=""),
    sa.Column("name", sa.String(120), nullable=False),
    sa.Column("email", sa.String(200), nullable=False, default=""),
    sa.Column("group", sa.String(80), nullable=False, default=""),
    sa.Column("joined", sa.Float, nullable=True),  # when a page first joined as this student
    sa.Index("ix_students_class", "class_id"),
)

attempts = sa.Table(
    "attempts",
    metadata,
    sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
    sa.Column("student_id", sa.Integer, sa.ForeignKey("students.id"), nullable=False),
    sa.Column("assignment", sa.String(80), nullable=False),
    sa.Column("variant", sa.String(80), nullable=False, default=""),
    sa.Column("submitted", sa.JSON, nullable=False),
    sa.Column("checks", sa.JSON, nullable=False),
    sa.Column("passed", sa.Boolean, nullable=False),
    sa.Column("at", sa.Float, nullable=False),
    sa.Index("ix_attempts_student", "student_id"),
)

__all__ = ["attempts", "classes", "metadata", "students"]
