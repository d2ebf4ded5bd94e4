! The lines of a dpmpm_vars_<group>.inc list as the objects of the group's namelist, in
! the list's order (which the echo keeps).
#undef VAR
#undef TEXT
#undef LOCAL
#define VAR(G, T, N, C, S, V) namelist /G/ N
#define TEXT(G, N, C, L, V, GS, NS) namelist /G/ N
#define LOCAL(G, T, N, S, V) namelist /G/ N
