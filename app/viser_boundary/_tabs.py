"""Tabs renamed in place: viser 1.1.1 sets a tab's label only when the tab is added."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any


def relabel_tabs(tab_group: Any, labels: Sequence[str]) -> None:
    """Give the tabs of ``tab_group`` the ``labels`` (in their order) and send the new
    labels to the page; the tabs, their contents and the selected tab stay."""
    tabs = list(tab_group._tab_handles)
    if len(tabs) != len(labels):
        raise ValueError(f"{len(labels)} labels for {len(tabs)} tabs")
    for tab, label in zip(tabs, labels, strict=True):
        tab._label = str(label)
    tab_group._rebuild_tab_props()
