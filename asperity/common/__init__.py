"""What every asperity theory shares, at the bottom: the GW functions F_n, safeguarded roots,
effective hydraulic apertures of gap distributions and Holm-Greenwood resistance."""
