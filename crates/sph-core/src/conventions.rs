//! What a run's numbers mean, in words: units, the plane-strain depth of 2D runs, the sign of
//! reaction forces, the columns of the recorded series. Results files carry these sentences
//! (the run driver writes them to `/meta`, the solvers to each `/series/<name>` as its
//! `description`), and the user guide quotes them (generated), so the file explains itself.

/// Units of every number written.
pub const UNITS: &str = "SI throughout: lengths in m, times in s, masses in kg, forces in N, \
     stresses and pressures in Pa, energies in J, angles in rad, velocities in m/s";

/// What a 2D run's extensive quantities are.
pub const PLANE_STRAIN: &str = "a 2D run is plane strain: forces, energies, masses, volumes \
     and areas are per unit depth along z (N/m, J/m, kg/m, m², m); positions and vectors are \
     written with z = 0";

/// The sign of the reaction forces of tools, grips and contacts.
pub const REACTIONS: &str = "a reaction force (`force_x`, `force_y`, `force_z`) is the force \
     the body exerts on the tool or grip, averaged over the interval since the previous row; \
     the tool or grip pushes or pulls the body with its negative (a platen pressing down on a \
     block reads force_y > 0, a grip pulling a strip to +x reads force_x < 0)";

/// The columns of a rigid tool's series.
pub const TOOL_SERIES: &str = "rigid tool: `time` (s); `displacement` its travel (m: along \
     its direction, or the length of its displacement when it follows a path or a velocity \
     curve); `force_x`, `force_y`, `force_z` (3D) the mean force the body exerts on the tool \
     (N; N/m in 2D); `contacts` the particles touching it in the last step; for a tool off a \
     straight line `displacement_x`, `displacement_y`, `displacement_z` (3D) its displacement \
     (m), and for a turning tool `angle` the angle it has turned (rad)";

/// The columns a tool with friction adds to [`TOOL_SERIES`] (after `contacts`).
pub const TOOL_FRICTION_SERIES: &str = "with friction: `friction_x`, `friction_y`, `friction_z` \
     (3D) the tangential part of that force, the mean friction force the body exerts on the tool \
     (N; N/m in 2D); `sticking` the fraction of the contacting particles that stuck in the last \
     step (0 with no contact)";

/// The columns of a named constraint's (grip's) series.
pub const GRIP_SERIES: &str = "named constraint (grip): `time` (s); `x`, `y`, `z` (3D) the \
     mean position of its particles (m); `force_x`, `force_y`, `force_z` (3D) the mean force the \
     body exerts on it over the interval (N; N/m in 2D): the force the grip applies to the \
     body is its negative";

/// The columns of an updated-Lagrangian body's contact-force series.
pub const CONTACT_SERIES: &str = "body-body contact (UL, TL): `time` (s); `x`, `y`, `z` (3D) the \
     total contact force the other bodies exert on this body (N; N/m in 2D), at the sample \
     time";

/// What `/probes/<name>` holds.
pub const PROBES: &str = "a probe follows a material point: `time` (s), `position` (m) and \
     `velocity` (m/s) of the point (the particle's, or the kernel-weighted average of its \
     neighbours' displacement and velocity), every step or every probe interval; \
     `fields/time` and `fields/<field>` the output fields asked for, at the monitor times";

#[cfg(test)]
mod tests {
    #[test]
    fn the_sentences_are_single_lines() {
        for s in [
            super::UNITS,
            super::PLANE_STRAIN,
            super::REACTIONS,
            super::TOOL_SERIES,
            super::TOOL_FRICTION_SERIES,
            super::GRIP_SERIES,
            super::CONTACT_SERIES,
            super::PROBES,
        ] {
            assert!(!s.contains('\n') && !s.contains("  "), "{s}");
        }
    }
}
