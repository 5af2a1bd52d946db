"""The model: every lesson of the textbook and the two articles, headless.

``kit`` is the contract and what every lesson uses; each domain (``analyzers``,
``mechanics``, ``vibration``, ``servo``, ``laser5``) holds its pages and, in
subpackages, its machinery; ``assignments`` poses tasks over any lesson. Nothing here
imports the view.
"""
