//! Every conversion from file units to tire-gap's internal units, in one place.
