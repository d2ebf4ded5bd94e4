! The lines of a dpmpm_vars_<group>.inc list as components of a config type, with their
! defaults; LOCAL variables are the reader's own.
#undef VAR
#undef TEXT
#undef LOCAL
#define VAR(G, T, N, C, S, V) T :: C S = V
#define TEXT(G, N, C, L, V, GS, NS) character(len=L) :: C = V
#define LOCAL(G, T, N, S, V)
