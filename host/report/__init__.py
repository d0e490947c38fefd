"""What people look at: views computed from trace folders, plots, the HTML report of a
session, the budget table and one-line progress. Reads trace folders; never runs a rig."""
