! The lines of a dpmpm_vars_<group>.inc list as statements giving the reader's local
! variables their defaults before the group is read.
#undef VAR
#undef TEXT
#undef LOCAL
#define VAR(G, T, N, C, S, V) N = V
#define TEXT(G, N, C, L, V, GS, NS) N = V
#define LOCAL(G, T, N, S, V) N = V
