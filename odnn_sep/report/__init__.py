"""Shared reporting helpers: JSON-ready conversion and matplotlib figure set-up."""
