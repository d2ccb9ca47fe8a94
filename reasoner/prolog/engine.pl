/*  Rule engine for compiled Logical English rulebooks.

    Each rulebook lives in its own module (named by the sha256 of its LE text), so several
    versions coexist.  Rules arrive as data from Python and are turned into terms here, never
    parsed from text: a fact or constant can only ever be an atom or a number.  Scenario facts
    are thread-local to the rulebook module and retracted after each question, so every
    question sees only its own scenario.
*/
:- module(gaps_engine,
          [ new_rulebook/2,             % +Module, +Functor-Arity list
            add_rule/4,                 % +Module, +Id, +HeadData, +BodyData
            ask/5                       % +Module, +FactsData, +GoalData, -Proofs, -WhyNot
          ]).
:- use_module(library(apply)).
:- use_module(library(lists)).

%!  new_rulebook(+M, +Decls) is det.
%   Declare the template predicates of rulebook module M, each also true of a scenario fact.
new_rulebook(M, Decls) :-
    thread_local(M:scenario_fact/1),
    dynamic(M:le_rule/4),
    forall(member(F-A, Decls), declare(M, F, A)).

declare(M, F, A) :-
    functor(H, F, A),
    dynamic(M:F/A),
    assertz(M:(H :- scenario_fact(H))).

%!  add_rule(+M, +Id, +HeadData, +BodyData) is det.
%   Add a compiled rule both as a clause (for plain queries) and as le_rule/4 (for proofs).
add_rule(M, Id, HeadD, BodyD) :-
    build_atom(HeadD, Head, [], E1),
    build_body(BodyD, Body, E1, Names),
    assertz(M:le_rule(Id, Head, Body, Names)),
    body_goal(Body, Goal),
    assertz(M:(Head :- Goal)).

build_atom([F|ArgsD], T, E0, E) :-
    foldl(build_arg, ArgsD, Args, E0, E),
    T =.. [F|Args].

build_arg(var-Name, V, E0, E) :- !,
    (   memberchk(Name-V0, E0) -> V = V0, E = E0 ; E = [Name-V|E0] ).
build_arg(X, X, E, E) :- ( atom(X) ; number(X) ), !.
build_arg(X, _, _, _) :- type_error(le_constant, X).

build_body([], [], E, E).
build_body([C|Cs], [B|Bs], E0, E) :- build_cond(C, B, E0, E1), build_body(Cs, Bs, E1, E).

build_cond(pos-AtomD, pos(A), E0, E) :- build_atom(AtomD, A, E0, E).
build_cond(not-BodyD, not(B), E0, E) :- build_body(BodyD, B, E0, E).

body_goal([], true).
body_goal([C], G) :- !, cond_goal(C, G).
body_goal([C|Cs], (G, Gs)) :- cond_goal(C, G), body_goal(Cs, Gs).

cond_goal(pos(A), A).
cond_goal(not(B), \+ G) :- body_goal(B, G).

%!  ask(+M, +FactsData, +GoalData, -Proofs, -WhyNot) is det.
%   Proofs: a proof tree per answer; WhyNot: why the goal failed (@none when it succeeded).
ask(M, FactsD, GoalD, Proofs, WhyNot) :-
    maplist(build_fact, FactsD, Facts),
    build_atom(GoalD, Goal, [], Names),
    setup_call_cleanup(
        forall(member(F, Facts), assertz(M:scenario_fact(F))),
        answers(M, Goal, Names, Proofs, WhyNot),
        retractall(M:scenario_fact(_))).

build_fact(D, F) :- build_atom(D, F, [], _).

answers(M, Goal, Names, Proofs, WhyNot) :-
    findall(D, (prove(M, Goal, T), tree_data(T, Names, D)), Proofs),
    (   Proofs == []
    ->  why_not(M, Goal, W), tree_data(W, Names, WhyNot)
    ;   WhyNot = @(none)
    ).

%   node(Goal, Status, RuleId, Children, VariableNames)
prove(M, G, node(G, fact, @(none), [], [])) :-
    M:scenario_fact(G).
prove(M, G, node(G, proved, Id, Kids, Names)) :-
    M:le_rule(Id, G, Body, Names),
    prove_body(M, Body, Kids).

prove_body(_, [], []).
prove_body(M, [C|Cs], [T|Ts]) :- prove_cond(M, C, T), prove_body(M, Cs, Ts).

prove_cond(M, pos(G), T) :- prove(M, G, T).
prove_cond(M, not(B), node(not(B), proved, @(none), Why, [])) :-
    \+ prove_body(M, B, _),
    why_not_body(M, B, Why).

%   Why a goal has no proof: for each rule whose head fits, the conditions up to the first
%   one that fails (taking the first way each earlier condition holds).
why_not(M, G, node(G, failed, @(none), Attempts, [])) :-
    findall(A, attempt(M, G, A), Attempts).

attempt(M, G, node(G2, failed, Id, Trees, Names)) :-
    copy_term(G, G2),
    M:le_rule(Id, G2, Body, Names),
    why_not_body(M, Body, Trees).

why_not_body(_, [], []).
why_not_body(M, [C|Cs], Trees) :-
    (   prove_cond(M, C, T)
    ->  Trees = [T|Rest], why_not_body(M, Cs, Rest)
    ;   failed_cond(M, C, F), Trees = [F]
    ).

failed_cond(M, pos(G), W) :- why_not(M, G, W).
failed_cond(M, not(B), node(not(B), failed, @(none), Proof, [])) :-
    once(prove_body(M, B, Proof)).

%   Trees as Python-friendly data: dicts, lists, atoms, numbers.
tree_data(node(G, S, Id, Kids, Names), Env0, _{sentence: D, status: S, rule: Id, children: KD}) :-
    append(Names, Env0, Env),
    goal_data(G, Env, D),
    trees_data(Kids, Env, KD).

trees_data([], _, []).
trees_data([K|Ks], Env, [D|Ds]) :- tree_data(K, Env, D), trees_data(Ks, Env, Ds).

goal_data(not(B), Env, ['$not', BD]) :- !, conds_data(B, Env, BD).
goal_data(G, Env, [F|AD]) :-
    G =.. [F|Args],
    args_data(Args, Env, AD).

conds_data([], _, []).
conds_data([C|Cs], Env, [D|Ds]) :- cond_data(C, Env, D), conds_data(Cs, Env, Ds).

args_data([], _, []).
args_data([A|As], Env, [D|Ds]) :- arg_data(A, Env, D), args_data(As, Env, Ds).

cond_data(pos(G), Env, D) :- goal_data(G, Env, D).
cond_data(not(B), Env, D) :- goal_data(not(B), Env, D).

arg_data(V, Env, _{var: Name}) :- var(V), !,
    (   member(Name-V0, Env), V0 == V -> true ; Name = '_' ).
arg_data(X, _, X).
