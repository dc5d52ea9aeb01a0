"""Greenwood-Williamson theories: the summits of a height map, GW and improved GW, the paper's
dimensionless forms and reduced curves."""
