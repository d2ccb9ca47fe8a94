/*  Rule engine for compiled Logical English rulebooks.

    Each rulebook lives in its own module (named by the sha256 of its LE text), so several
    versions coexist.  Rules arrive as data from Python and are turned into terms here with
    =.., never parsed from text: a fact or constant can only ever be an atom or a number.
    Scenario facts (and scenario rules) are thread-local to the rulebook module and retracted
    after each question, so every question sees only its own scenario.

    Two ways to ask: plain (the compiled clauses, fast: answers only) and with proofs (a
    meta-interpreter over the same rules kept as data, giving a proof tree per answer, or
    why the question has no answer).  Every question runs under an inference limit, so a
    rulebook that recurses without end gives an error instead of hanging the process.

    Data from Python (janus turns a tuple into a '-' term):
      argument   atom | number | v-Name | l-[Arg] | -(e, Op, [Arg]) | s-[Functor|Args]
      condition  pos-[Functor|Args] | not-[Cond] | or-[[Cond]] | -(forall, [Cond], [Cond])
                 | -(agg, Kind, Result, Each, [Cond])
      fact       [Functor|Args] | -(rule, Id, [Functor|Args], [Cond])
*/
:- module(gaps_engine,
          [ new_rulebook/2,             % +Module, +Functor-Arity list
            add_rule/4,                 % +Module, +Id, +HeadData, +BodyData
            add_rules/2,                % +Module, +List of Id-HeadData-BodyData
            drop_rulebook/1,            % +Module
            ask/5,                      % +Module, +FactsData, +GoalData, -Proofs, -WhyNot
            ask_plain/4,                % +Module, +FactsData, +CondsData, -Answers
            ask_proofs/5,               % +Module, +FactsData, +CondsData, -Answers, -WhyNot
            ask_first/6,                % +Module, +FactsData, +GoalsData, -Index, -Proofs, -WhyNot
            first_holding/4,            % +Module, +FactsData, +GoalsData, -Index
            ask_all/4,                  % +Module, +FactsData, +Questions, -Results
            holds/3,                    % +Module, +FactsData, +GoalData
            holds/4,                    % +Module, +FactsData, +GoalData, -Bool
            holds_each/4,               % +Module, +AtomsData, +Questions, -Answers
            clause_text/3               % +Module, +Id, -Text
          ]).
:- use_module(library(apply)).
:- use_module(library(lists)).
:- use_module(library(pairs)).
:- use_module(library(yall)).
:- use_module(library(solution_sequences)).

:- dynamic inference_limit/1.
inference_limit(20000000).

:- initialization(nb_setval(le_facts, facts{})).

%!  new_rulebook(+M, +Decls) is det.
%   Declare the template predicates of rulebook module M, each also true of a scenario fact.
new_rulebook(M, Decls) :-
    thread_local(M:scenario_rule/4),
    dynamic(M:le_rule/4),
    forall(member(F-A, Decls), declare(M, F, A)),
    assertz(M:(isa_fact(X, Y) :- gaps_engine:le_fact(is_a, is_a(X, Y)))),
    assertz(M:(isa_rule(X, Y) :- M:scenario_rule(_, is_a(X, Y), B, _), gaps_engine:scenario_body(M, B))),
    assertz(M:(is_a(X, Y) :- gaps_engine:isa(M, X, Y))).

declare(_, is_a, 2) :- !.
declare(_, F, A) :-
    functor(H, F, A),
    predicate_property(system:H, built_in), !,
    throw(error(le_reserved(F, A), _)).
declare(M, F, A) :-
    functor(H, F, A),
    assertz(M:(H :- gaps_engine:le_fact(F, H))),
    assertz(M:(H :- M:scenario_rule(_, H, B, _), gaps_engine:scenario_body(M, B))).

%   A scenario rule's body, proved.  The clauses above name their functor and their module's
%   scenario rules themselves: a question calls a template predicate some 70 times, and a
%   functor/3 and a meta-call of the (almost always empty) scenario rules each time were a
%   fifth of asking.
scenario_body(M, Body) :-
    body_goal(M, Body, G),
    call(M:G).

%!  add_rule(+M, +Id, +HeadData, +BodyData) is det.
%   Add a compiled rule both as a clause (for plain questions) and as le_rule/4 (for proofs).
add_rule(M, Id, HeadD, BodyD) :-
    build_rule(HeadD, BodyD, Head, Body, Names),
    assertz(M:le_rule(Id, Head, Body, Names)),
    body_goal(M, Body, Goal),
    (   Head = is_a(X, Y), Body == []
    ->  assertz(M:isa_fact(X, Y))
    ;   Head = is_a(X, Y)
    ->  assertz(M:(isa_rule(X, Y) :- Goal))
    ;   assertz(M:(Head :- Goal))
    ).

add_rules(M, Rules) :-
    forall(member(-(Id, H, B), Rules), add_rule(M, Id, H, B)).

%!  drop_rulebook(+M) is det.
%   Forget everything of a rulebook module (after a load that did not complete).
drop_rulebook(M) :-
    forall(( current_predicate(M:P/A), functor(H, P, A),
             predicate_property(M:H, dynamic), \+ predicate_property(M:H, imported_from(_)) ),
           retractall(M:H)).

build_rule(HeadD, BodyD, Head, Body, Names) :-
    build_atom(HeadD, Head, [], E1),
    build_body(BodyD, Body, E1, Names).

% -- building terms from data --------------------------------------------------------------

build_atom([F|ArgsD], T, E0, E) :-
    atom(F),
    foldl(build_arg, ArgsD, Args, E0, E),
    T =.. [F|Args].

build_arg(v-Name, V, E0, E) :- !,
    (   memberchk(Name-V0, E0) -> V = V0, E = E0 ; E = [Name-V|E0] ).
build_arg(l-Items, L, E0, E) :- !, foldl(build_arg, Items, L, E0, E).
build_arg(-(e, Op, ArgsD), T, E0, E) :- !,
    memberchk(Op, [+, -, *, /, neg]),
    foldl(build_arg, ArgsD, Args, E0, E),
    (   Op == neg -> Args = [A], T = -(A) ; T =.. [Op|Args] ).
build_arg(s-AtomD, T, E0, E) :- !, build_atom(AtomD, T, E0, E).
build_arg(X, X, E, E) :- ( atom(X) ; number(X) ), !.
build_arg(X, _, _, _) :- type_error(le_constant, X).

build_body([], [], E, E).
build_body([C|Cs], [B|Bs], E0, E) :- build_cond(C, B, E0, E1), build_body(Cs, Bs, E1, E).

build_cond(pos-AtomD, pos(A), E0, E) :- build_atom(AtomD, A, E0, E).
build_cond(not-BodyD, not(B), E0, E) :- build_body(BodyD, B, E0, E).
build_cond(or-AltsD, or(Alts), E0, E) :- foldl(build_body, AltsD, Alts, E0, E).
build_cond(-(forall, CasesD, ThenD), forall(Cases, Then), E0, E) :-
    build_body(CasesD, Cases, E0, E1), build_body(ThenD, Then, E1, E).
build_cond(-(agg, Kind, ResD, EachD, BodyD), agg(Kind, R, X, B), E0, E) :-
    memberchk(Kind, [sum, max, min, count, bag, set]),
    build_arg(ResD, R, E0, E1), build_arg(EachD, X, E1, E2), build_body(BodyD, B, E2, E).

build_fact(-(rule, Id, HeadD, BodyD), rule(Id, H, B, Names)) :- !, build_rule(HeadD, BodyD, H, B, Names).
build_fact(D, F) :- build_atom(D, F, [], _).

% -- compiling bodies to goals --------------------------------------------------------------

body_goal(_, [], true).
body_goal(M, [C], G) :- !, cond_goal(M, C, G).
body_goal(M, [C|Cs], (G, Gs)) :- cond_goal(M, C, G), body_goal(M, Cs, Gs).

cond_goal(M, pos(A), G) :- atom_goal(M, A, G).
cond_goal(M, not(B), \+ G) :- body_goal(M, B, G).
cond_goal(M, or(Alts), G) :- maplist(body_goal(M), Alts, Gs), disjunction(Gs, G).
cond_goal(M, forall(C, T), \+ (GC, \+ GT)) :- body_goal(M, C, GC), body_goal(M, T, GT).
cond_goal(M, agg(K, R, X, B), gaps_engine:aggregate(K, R, X, M:G)) :- body_goal(M, B, G).

disjunction([G], G) :- !.
disjunction([G|Gs], (G ; R)) :- disjunction(Gs, R).

atom_goal(_, A, gaps_engine:builtin(A)) :- builtin_atom(A), !.
atom_goal(_, A, G) :-
    A =.. [F|Args],
    (   include(is_expr, Args, []) -> G = A
    ;   G = (gaps_engine:eval_args(Args, Vs), A2), A2 =.. [F|Vs]
    ).

is_expr(X) :- compound(X), functor(X, Op, N), expr_op(Op, N).
expr_op(+, 2). expr_op(-, 2). expr_op(*, 2). expr_op(/, 2). expr_op(-, 1).

builtin_atom(A) :- functor(A, F, N), builtin_pred(F, N).
builtin_pred(le_known, 1).        builtin_pred(le_unknown, 1).
builtin_pred(le_before, 2).       builtin_pred(le_after, 2).
builtin_pred(le_before_or_equal, 2). builtin_pred(le_after_or_equal, 2).
builtin_pred(le_immediately_before, 2). builtin_pred(le_days_after, 3).
builtin_pred(<, 2). builtin_pred(=<, 2). builtin_pred(>, 2). builtin_pred(>=, 2).
builtin_pred(le_eq, 2). builtin_pred(le_neq, 2).
builtin_pred(le_member, 2). builtin_pred(le_not_member, 2).
builtin_pred(le_length, 2). builtin_pred(le_sum_list, 2).
builtin_pred(le_max_list, 2). builtin_pred(le_min_list, 2).

% -- built-ins: they fail (never raise) on values of the wrong kind ---------------------------

eval(X, V) :- number(X), !, V = X.
eval(X, V) :- is_expr(X), ground(X), !, arith(X, V).
eval(X, X).

%   Arithmetic one operation at a time, each within the integer budget: the inference limit
%   counts a multiplication as one step whatever its size, so a rule squaring a number forty
%   times took 2 GB and a minute (and the resource error was read as "no answer").  An
%   operation on values that are no numbers fails, as a comparison of the wrong kind does;
%   running out of memory is never taken for a failure.
:- dynamic max_integer_bits/1.
max_integer_bits(4096).

arith(X, V) :- number(X), !, V = X.
arith(X, V) :-
    compound(X), compound_name_arguments(X, Op, Args0),
    maplist(arith, Args0, Args),
    maplist(number, Args),
    product_fits(Op, Args),
    compound_name_arguments(E, Op, Args),
    catch(V is E, error(Error, _), arith_error(Error)),
    integer_fits(V).

product_fits(*, [A, B]) :-
    integer(A), integer(B), A =\= 0, B =\= 0, !,
    integer_fits_bits(msb(abs(A)) + msb(abs(B)) + 2).
product_fits(_, _).

integer_fits(V) :- ( integer(V), V =\= 0 -> integer_fits_bits(msb(abs(V)) + 1) ; true ).
integer_fits_bits(Expr) :-
    max_integer_bits(Max),
    Bits is Expr,
    (   Bits =< Max -> true ; throw(error(le_limit(integer_bits(Max)), _)) ).

arith_error(resource_error(R)) :- !, throw(error(le_resource(R), _)).
arith_error(_) :- fail.

eval_args([], []).
eval_args([A|As], [V|Vs]) :- eval(A, V), eval_args(As, Vs).

num2(A, B, X, Y) :- eval(A, X), number(X), eval(B, Y), number(Y).

builtin(le_known(X)) :- nonvar(X).
builtin(le_unknown(X)) :- var(X).
builtin(le_before(A, B)) :- num2(A, B, X, Y), X < Y.
builtin(le_after(A, B)) :- num2(A, B, X, Y), X > Y.
builtin(le_before_or_equal(A, B)) :- num2(A, B, X, Y), X =< Y.
builtin(le_after_or_equal(A, B)) :- num2(A, B, X, Y), X >= Y.
builtin(le_immediately_before(A, B)) :-
    (   var(A), eval(B, Y), number(Y) -> A is Y - 86400
    ;   num2(A, B, X, Y), X =:= Y - 86400
    ).
builtin(le_days_after(A, N, B)) :-
    (   var(A), eval(N, K), number(K), eval(B, Y), number(Y) -> A is Y + K * 86400
    ;   var(N), num2(A, B, X, Y) -> N is (X - Y) / 86400
    ;   eval(A, X), number(X), eval(N, K), number(K), eval(B, Y), number(Y), X =:= Y + K * 86400
    ).
builtin(A < B) :- num2(A, B, X, Y), X < Y.
builtin(A =< B) :- num2(A, B, X, Y), X =< Y.
builtin(A > B) :- num2(A, B, X, Y), X > Y.
builtin(A >= B) :- num2(A, B, X, Y), X >= Y.
builtin(le_eq(A, B)) :- le_eq(A, B).
builtin(le_neq(A, B)) :- \+ le_eq(A, B).
builtin(le_member(X, L)) :- is_list(L), member(X, L).
builtin(le_not_member(X, L)) :- is_list(L), \+ memberchk(X, L).
builtin(le_length(L, N)) :- is_list(L), length(L, K), le_eq(N, K).
builtin(le_sum_list(N, L)) :- is_list(L), sum_numbers(L, S), le_eq(N, S).
builtin(le_max_list(N, L)) :- is_list(L), L \== [], maplist(number, L), max_list(L, S), le_eq(N, S).
builtin(le_min_list(N, L)) :- is_list(L), L \== [], maplist(number, L), min_list(L, S), le_eq(N, S).

%   `=` and `is`: arithmetic is evaluated, numbers compare by value, anything else unifies.
le_eq(A, B) :-
    eval(A, X), eval(B, Y),
    (   number(X), number(Y) -> X =:= Y
    ;   var(X), number(Y) -> X = Y
    ;   number(X), var(Y) -> Y = X
    ;   X = Y
    ).

sum_numbers(L, S) :- foldl(add_number, L, 0, S).
add_number(X, S0, S) :- number(X), S is S0 + X.

aggregate(Kind, R, X, G) :-
    findall(X, G, L),
    aggregate_list(Kind, L, V),
    le_eq(R, V).

aggregate_list(sum, L, S) :- sum_numbers(L, S).
aggregate_list(max, L, S) :- L \== [], maplist(number, L), max_list(L, S).
aggregate_list(min, L, S) :- L \== [], maplist(number, L), min_list(L, S).
aggregate_list(count, L, N) :- length(L, N).
aggregate_list(bag, L, L).
aggregate_list(set, L, S) :- sort(L, S).

% -- is_a: the ontology with transitivity, cut short on a loop --------------------------------

isa(M, X, Y) :-
    isa_enter(X-Y, S),
    isa_steps(M, X, Y),
    b_setval(le_isa, S).

%   The is_a questions in progress (a backtrackable global): a question that is a variant of
%   one of them is a loop and fails.
isa_enter(Key0, S) :-
    (   nb_current(le_isa, S) -> true ; S = [] ),
    copy_term(Key0, Key),
    \+ ( member(K, S), K =@= Key ),
    b_setval(le_isa, [Key|S]).

%   X is a Y: stated (a fact), concluded by a rule, or through a stated X is a Z.
isa_steps(M, X, Y) :- M:isa_fact(X, Y).
isa_steps(M, X, Y) :- M:isa_rule(X, Y).
isa_steps(M, X, Y) :- M:isa_fact(X, Z), Z \== Y, isa(M, Z, Y).

% -- asking ---------------------------------------------------------------------------------

%   The scenario's facts live in a backtrackable global for the question (a dict from functor
%   to facts), so asking costs no assert or retract; its rules (rare) are thread-local clauses.
with_scenario(M, FactsD, Goal) :-
    in_scenario(M, FactsD, limited(Goal)).

%   The scenario set up for Goal, which asks its questions itself (each under `limited`).
in_scenario(M, FactsD, Goal) :-
    build_facts(FactsD, Facts, Rules),
    facts_dict(Facts, Dict),
    b_setval(le_facts, Dict),
    (   Rules == []
    ->  call(Goal)
    ;   setup_call_cleanup(
            forall(member(R, Rules), assertz(M:R)),
            Goal,
            retractall(M:scenario_rule(_, _, _, _)))
    ).

build_facts([], [], []).
build_facts([D|Ds], Fs, Rs) :-
    (   D = -(rule, _, _, _)
    ->  build_fact(D, rule(Id, H, B, Names)), Rs = [scenario_rule(Id, H, B, Names)|Rs1], Fs = Fs1
    ;   D = [F|Args], atom(F), maplist(atomic, Args)
    ->  T =.. D, Fs = [T|Fs1], Rs = Rs1
    ;   build_fact(D, T), Fs = [T|Fs1], Rs = Rs1
    ),
    build_facts(Ds, Fs1, Rs1).

facts_dict(Facts, Dict) :-
    map_list_to_pairs(fact_key, Facts, Pairs),
    pairs_dict(Pairs, Dict).

%   The facts' dict from Key-Fact pairs (in the facts' order).
pairs_dict(Pairs0, Dict) :-
    keysort(Pairs0, Pairs),
    group_pairs_by_key(Pairs, Groups),
    dict_pairs(Dict, facts, Groups).

fact_key(F, K) :- functor(F, K, _).

%!  le_fact(?Fact) is nondet.
%   A fact of the question's scenario (a fresh copy when it has variables).
le_fact(H) :-
    functor(H, K, _),
    le_fact(K, H).

%   le_fact/1 with the fact's functor name K given.
le_fact(K, H) :-
    nb_current(le_facts, D),
    get_dict(K, D, L),
    member(F, L),
    (   ground(F) -> H = F ; copy_term(F, H) ).

limited(Goal) :-
    nb_setval(le_isa, []),
    why_budget(Budget), nb_setval(le_why, Budget),
    inference_limit(Limit),
    catch(call_with_inference_limit(Goal, Limit, R), E, limit_error(E)),
    (   R == inference_limit_exceeded
    ->  throw(error(le_limit(Limit), _))
    ;   true
    ).

limit_error(error(resource_error(R), _)) :- !, throw(error(le_resource(R), _)).
limit_error(E) :- throw(E).

%!  holds(+M, +FactsData, +GoalData) is semidet.
%   Plain yes/no for one sentence: the fastest way to ask.
holds(M, FactsD, GoalD) :-
    in_scenario(M, FactsD, holds_plainly(M, GoalD, _, _)).

%   The sentence (its data; Goal and Names: the term built from it) holds in the scenario set,
%   by the compiled clauses, under a question limit.
holds_plainly(M, GoalD, Goal, Names) :-
    build_atom(GoalD, Goal, [], Names),
    atom_goal(M, Goal, G),
    limited(once(M:G)).

holds(M, FactsD, GoalD, Bool) :-
    (   holds(M, FactsD, GoalD) -> Bool = true ; Bool = false ).

%!  holds_each(+M, +AtomsData, +Questions, -Answers) is det.
%   Several sentences, each on its own scenario, each asked as holds/3 asks it (its scenario
%   set up alone, its own question limit): a regression's thousands of questions in one call,
%   not one call each.  The questions share their sentences: AtomsData holds each once, and a
%   question is the 0-based places of its goal and then of its facts among them, each built
%   once here (a question still gets fresh variables of its own; a sentence is an atom's data,
%   never a scenario rule).  Answers: true or false per
%   question, or _{error: Message} where it raised an error (Message: its text, what holds/4
%   raises); an error or a failure in building a sentence is its questions' own, as in holds/3.
holds_each(M, AtomsD, Questions, Answers) :-
    maplist(built_atom, AtomsD, Built),
    Atoms =.. [atoms|Built],
    maplist(holds_placed(M, Atoms), Questions, Answers).

%   An atom's data built once for every question it is in, with its functor name (what its
%   question's facts are indexed by).
built_atom(D, B) :-
    catch(( build_atom(D, T, [], _) -> functor(T, K, _), ( ground(T) -> B = ground(K-T) ; B = open(K-T) )
          ; B = fail ), E,
          B = error(E)).

holds_placed(M, Atoms, [G|Fs], Answer) :-
    catch(( holds_placed(M, Atoms, G, Fs) -> Answer = true ; Answer = false ), E,
          ( message_to_string(E, S), Answer = _{error: S} )).

%   As holds/3 with the facts and the goal built: the facts first, then the goal.
holds_placed(M, Atoms, G, Fs) :-
    maplist(placed(Atoms), Fs, Pairs),
    placed(Atoms, G, _-Goal),
    pairs_dict(Pairs, Dict),
    b_setval(le_facts, Dict),
    atom_goal(M, Goal, Call),
    limited(once(M:Call)).

placed(Atoms, I, T) :-
    I1 is I + 1,
    arg(I1, Atoms, B),
    placed_(B, T).

placed_(ground(T), T).
placed_(open(T0), T) :- copy_term(T0, T).
placed_(error(E), _) :- throw(E).

%!  ask_plain(+M, +FactsData, +CondsData, -Answers) is det.
%   Every way the conditions hold, each as the conditions' data with the bindings filled in.
ask_plain(M, FactsD, CondsD, Answers) :-
    in_scenario(M, FactsD, answer_one(M, plain-CondsD, Answers)).

%!  ask_proofs(+M, +FactsData, +CondsData, -Answers, -WhyNot) is det.
%   Answers: Data-Trees per proof; WhyNot: why the conditions have no proof (@none otherwise).
ask_proofs(M, FactsD, CondsD, Answers, WhyNot) :-
    in_scenario(M, FactsD, answer_one(M, proofs-CondsD, [Answers, WhyNot])).

%!  ask_all(+M, +FactsData, +Questions, -Results) is det.
%   Several questions on one scenario, each answered as ask_plain/4 (plain-CondsData: Answers)
%   or ask_proofs/5 (proofs-CondsData: [Answers, WhyNot]) answers it, a question limit each;
%   the facts are built and indexed once.
ask_all(M, FactsD, Questions, Results) :-
    in_scenario(M, FactsD, maplist(answer_one(M), Questions, Results)).

answer_one(M, plain-CondsD, Answers) :-
    build_body(CondsD, Conds, [], Names),
    body_goal(M, Conds, Goal),
    limited(findall(D, (M:Goal, conds_data(Conds, Names, D)), Answers)).
answer_one(M, proofs-CondsD, [Answers, WhyNot]) :-
    build_body(CondsD, Conds, [], Names),
    limited(proofs_or_why(M, Conds, Names, Answers, WhyNot)).

proofs_or_why(M, Conds, Names, Answers, WhyNot) :-
    findall(D-TD, ( prove_body(M, Conds, Ts, 0), conds_data(Conds, Names, D),
                    trees_data(Ts, Names, TD) ), Answers),
    (   Answers == []
    ->  why_not_body(M, Conds, Ws, 0), trees_data(Ws, Names, WhyNot)
    ;   WhyNot = @(none)
    ).

%!  ask(+M, +FactsData, +GoalData, -Proofs, -WhyNot) is det.
%   One sentence: its first proof tree (Proofs = [Tree], the proof a search for all of them
%   finds first), or why it has none (Proofs = [], WhyNot the tree; @none when it has one).
%   Every caller shows one proof; searching on for the others took a third of the time.
ask(M, FactsD, GoalD, Proofs, WhyNot) :-
    build_atom(GoalD, Goal, [], Names),
    with_scenario(M, FactsD, first_answer(M, Goal, Names, Proofs, WhyNot)).

%!  ask_first(+M, +FactsData, +GoalsData, -Index, -Proofs, -WhyNot) is det.
%   Several sentences in turn on one scenario, each asked as holds/3 and then ask/5 would ask
%   it (a question limit each): the first with a proof, its 0-based Index and that proof; Index
%   -1 when none has one, with what ask/5 gives for the first.  The scenario is built once:
%   shipping and indexing the facts for every question was a third of judging a verdict.
ask_first(M, FactsD, [First|GoalsD], Index, Proofs, WhyNot) :-
    in_scenario(M, FactsD, first_proved(M, [First|GoalsD], First, 0, Index, Proofs, WhyNot)).

first_proved(M, [], First, _, -1, Proofs, WhyNot) :-
    build_atom(First, Goal, [], Names),
    limited(first_answer(M, Goal, Names, Proofs, WhyNot)).
first_proved(M, [GD|GDs], First, I, Index, Proofs, WhyNot) :-
    (   holds_plainly(M, GD, Goal, Names), limited(first_answer(M, Goal, Names, [P], W))
    ->  Index = I, Proofs = [P], WhyNot = W
    ;   I1 is I + 1,
        first_proved(M, GDs, First, I1, Index, Proofs, WhyNot)
    ).

%!  first_holding(+M, +FactsData, +GoalsData, -Index) is det.
%   The 0-based index of the first of the sentences that holds/3 says holds on one scenario,
%   or -1.
first_holding(M, FactsD, GoalsD, Index) :-
    in_scenario(M, FactsD, first_true(M, GoalsD, 0, Index)).

first_true(_, [], _, -1).
first_true(M, [GD|GDs], I, Index) :-
    (   holds_plainly(M, GD, _, _)
    ->  Index = I
    ;   I1 is I + 1, first_true(M, GDs, I1, Index)
    ).

first_answer(M, Goal, Names, Proofs, WhyNot) :-
    (   once(prove(M, Goal, T, 0))
    ->  tree_data(T, Names, D), Proofs = [D], WhyNot = @(none)
    ;   Proofs = [], why_not(M, Goal, W, 0), tree_data(W, Names, WhyNot)
    ).

% -- proofs -----------------------------------------------------------------------------------
%   node(Sentence, Status, RuleId, Children, VariableNames)

max_depth(2000).

prove(M, G0, T, D) :-
    max_depth(Max),
    (   D < Max -> true ; throw(error(le_limit(depth(Max)), _)) ),
    D1 is D + 1,
    prove_(M, G0, T, D1).

prove_(_, G0, node(G, builtin, @(none), [], []), _) :-
    builtin_atom(G0), !,
    evaluated(G0, G),
    builtin(G).
prove_(M, is_a(X, Y), T, D) :- !,
    isa_enter(X-Y, S),
    prove_isa(M, X, Y, T, D),
    b_setval(le_isa, S).
prove_(M, G0, T, D) :-
    evaluated(G0, G),
    prove_user(M, G, T, D).

%   The goal with its ground arithmetic arguments evaluated (eval_args): most goals have none,
%   and are their own result without being taken apart and rebuilt.
evaluated(G0, G) :-
    (   arg(_, G0, A), is_expr(A), ground(A)
    ->  G0 =.. [F|As], eval_args(As, Vs), G =.. [F|Vs]
    ;   G = G0
    ).

prove_user(_, G, node(G, fact, @(none), [], []), _) :-
    le_fact(G).
prove_user(M, G, node(G, proved, @(none), Kids, Names), D) :-
    M:scenario_rule(_, G, Body, Names),
    prove_body(M, Body, Kids, D).
prove_user(M, G, node(G, Status, Id, Kids, Names), D) :-
    M:le_rule(Id, G, Body, Names),
    prove_body(M, Body, Kids, D),
    ( Body == [] -> Status = fact ; Status = proved ).

prove_isa(M, X, Y, T, D) :- prove_user(M, is_a(X, Y), T, D).
prove_isa(M, X, Y, node(is_a(X, Y), proved, @(none), [T1, T2], []), D) :-
    isa_fact_proof(M, X, Z, T1), Z \== Y,
    prove(M, is_a(Z, Y), T2, D).

isa_fact_proof(_, X, Z, node(is_a(X, Z), fact, @(none), [], [])) :- le_fact(is_a(X, Z)).
isa_fact_proof(M, X, Z, node(is_a(X, Z), fact, Id, [], [])) :- M:le_rule(Id, is_a(X, Z), [], _).

prove_body(_, [], [], _).
prove_body(M, [C|Cs], Trees, D) :-
    prove_cond(M, C, Ts, D),
    append(Ts, Rest, Trees),
    prove_body(M, Cs, Rest, D).

%   Each condition gives a list of trees: a disjunction gives the trees of its chosen branch.
prove_cond(M, pos(G), [T], D) :- prove(M, G, T, D).
prove_cond(M, not(B), [node(not(B), proved, @(none), Why, [])], D) :-
    \+ prove_body(M, B, _, D),
    why_not_body(M, B, Why, D).
prove_cond(M, or(Alts), Ts, D) :-
    member(Alt, Alts),
    prove_body(M, Alt, Ts, D).
prove_cond(M, forall(C, G), [node(forall(C, G), proved, @(none), Kids, [])], D) :-
    \+ ( prove_body(M, C, _, D), \+ prove_body(M, G, _, D) ),
    findall(K, ( limit(10, prove_body(M, C, TC, D)), once(prove_body(M, G, TG, D)),
                 append(TC, TG, TK), K = node(and(C, G), proved, @(none), TK, []) ), Kids).
prove_cond(M, agg(Kind, R, X, B), [node(agg(Kind, R, X, B), proved, @(none), Kids, [])], D) :-
    findall(X-Ts, prove_body(M, B, Ts, D), Pairs),
    pairs_keys_values(Pairs, Xs, TreeLists),
    aggregate_list(Kind, Xs, V),
    le_eq(R, V),
    length(TreeLists, N), Keep is min(N, 20), length(Shown, Keep), append(Shown, _, TreeLists),
    append(Shown, Kids).

% -- why not --------------------------------------------------------------------------------
%   Why a goal has no proof: for each rule whose head fits, the conditions up to the first
%   one that fails (taking the first way each earlier condition holds).  Depth-limited.

%   An explanation is bounded in depth and in size: past them a failed goal is left
%   unexplored (marked `truncated`), so a why-not never costs more than the question.

max_why_depth(12).
why_budget(1500).

why_not(_, G, node(G, failed, @(none), [], []), _) :-
    builtin_atom(G), !.
why_not(_, G, node(G, failed, @(none), '$truncated', []), D) :-
    max_why_depth(Max), D >= Max, !.
why_not(_, G, node(G, failed, @(none), '$truncated', []), _) :-
    \+ why_spend, !.
why_not(M, G, node(G, failed, @(none), Attempts, []), D) :-
    D1 is D + 1,
    (   G = is_a(_, _) -> Rules = isa ; Rules = user ),
    findall(A, attempt(Rules, M, G, A, D1), Attempts).

attempt(_, M, G, node(G2, failed, Id, Trees, Names), D) :-
    copy_term(G, G2),
    M:le_rule(Id, G2, Body, Names),
    Body \== [],
    why_not_body(M, Body, Trees, D).
attempt(_, M, G, node(G2, failed, @(none), Trees, Names), D) :-
    copy_term(G, G2),
    M:scenario_rule(_, G2, Body, Names),
    why_not_body(M, Body, Trees, D).

why_spend :-
    nb_current(le_why, B), B > 0,
    B1 is B - 1, nb_setval(le_why, B1).

why_not_body(_, [], [], _).
why_not_body(M, [C|Cs], Trees, D) :-
    (   once(prove_cond(M, C, Ts, D))
    ->  append(Ts, Rest, Trees), why_not_body(M, Cs, Rest, D)
    ;   failed_cond(M, C, F, D), Trees = [F]
    ).

failed_cond(M, pos(G), W, D) :- why_not(M, G, W, D).
failed_cond(M, not(B), node(not(B), failed, @(none), Proof, []), D) :-
    once(prove_body(M, B, Proof, D)).
failed_cond(M, or(Alts), node(or(Alts), failed, @(none), Kids, []), D) :-
    findall(K, ( member(Alt, Alts), why_not_body(M, Alt, W, D), alternative_node(Alt, W, K) ), Kids).

failed_cond(M, forall(C, G), node(forall(C, G), failed, @(none), Kids, []), D) :-
    (   once(( prove_body(M, C, TC, D), \+ prove_body(M, G, _, D), why_not_body(M, G, WG, D) ))
    ->  append(TC, WG, Ks), Kids = [node(and(C, G), failed, @(none), Ks, [])]
    ;   Kids = []
    ).
failed_cond(_, agg(K, R, X, B), node(agg(K, R, X, B), failed, @(none), [], []), _).

alternative_node([_], [W], W) :- !.
alternative_node(Alt, W, node(and(Alt), failed, @(none), W, [])).

% -- trees and answers as Python-friendly data: dicts, lists, atoms, numbers --------------------

tree_data(node(G, S, Id, '$truncated', Names), Env0,
          _{sentence: D, status: S, rule: Id, children: [], truncated: true}) :- !,
    append(Names, Env0, Env),
    goal_data(G, Env, D).
tree_data(node(G, S, Id, Kids, Names), Env0, _{sentence: D, status: S, rule: Id, children: KD}) :-
    append(Names, Env0, Env),
    goal_data(G, Env, D),
    trees_data(Kids, Env, KD).

trees_data([], _, []).
trees_data([K|Ks], Env, [D|Ds]) :- tree_data(K, Env, D), trees_data(Ks, Env, Ds).

alts_data([], _, []).
alts_data([A|As], Env, [D|Ds]) :- conds_data(A, Env, D), alts_data(As, Env, Ds).

conds_data([], _, []).
conds_data([C|Cs], Env, [D|Ds]) :- cond_data(C, Env, D), conds_data(Cs, Env, Ds).

cond_data(pos(G), Env, D) :- goal_data(G, Env, D).
cond_data(not(B), Env, D) :- goal_data(not(B), Env, D).
cond_data(or(A), Env, D) :- goal_data(or(A), Env, D).
cond_data(forall(C, G), Env, D) :- goal_data(forall(C, G), Env, D).
cond_data(agg(K, R, X, B), Env, D) :- goal_data(agg(K, R, X, B), Env, D).

goal_data(not(B), Env, ['$not', BD]) :- !, conds_data(B, Env, BD).
goal_data(or(Alts), Env, ['$or', AD]) :- !, alts_data(Alts, Env, AD).
goal_data(and(B), Env, ['$and', BD]) :- !, conds_data(B, Env, BD).
goal_data(and(C, G), Env, ['$and', BD]) :- !, append(C, G, B), conds_data(B, Env, BD).
goal_data(forall(C, G), Env, ['$forall', CD, GD]) :- !, conds_data(C, Env, CD), conds_data(G, Env, GD).
goal_data(agg(K, R, X, B), Env, ['$agg', K, RD, XD, BD]) :- !,
    arg_data(R, Env, RD), arg_data(X, Env, XD), conds_data(B, Env, BD).
goal_data(G, Env, [F|AD]) :-
    G =.. [F|Args],
    args_data(Args, Env, AD).

args_data([], _, []).
args_data([A|As], Env, [D|Ds]) :- arg_data(A, Env, D), args_data(As, Env, Ds).

arg_data(V, Env, _{var: Name}) :- var(V), !,
    (   member(Name-V0, Env), V0 == V -> true ; Name = '_' ).
arg_data(L, Env, _{list: D}) :- is_list(L), !, args_data(L, Env, D).
arg_data(X, Env, _{expr: [Op|D]}) :- is_expr(X), !,
    X =.. [Op0|Args], ( Op0 == (-), Args = [_] -> Op = neg ; Op = Op0 ), args_data(Args, Env, D).
arg_data(X, Env, _{sentence: D}) :- compound(X), !, goal_data(X, Env, D).
arg_data(X, _, X).

%!  clause_text(+M, +Id, -Text) is det.
%   The compiled clause of rule Id as Prolog text (for `gaps rules prolog`).
clause_text(M, Id, Text) :-
    M:le_rule(Id, Head, Body, Names),
    body_goal(M, Body, Goal0),
    strip_module_goal(Goal0, Goal),
    bind_names(Names, []),
    (   Head = is_a(X, Y), Body == [] -> H = isa_fact(X, Y)
    ;   Head = is_a(X, Y) -> H = isa_rule(X, Y)
    ;   H = Head
    ),
    (   Goal == true -> C = H ; C = (H :- Goal) ),
    with_output_to(string(Text), portray_clause(C)).

bind_names([], _).
bind_names([N-V|T], Used) :- var(V), !,
    prolog_var_name(N, Used, PN), V = '$VAR'(PN), bind_names(T, [PN|Used]).
bind_names([_|T], Used) :- bind_names(T, Used).

prolog_var_name(N, Used, PN) :-
    atom_codes(N, Cs),
    split_words(Cs, Words),
    maplist(capitalise, Words, Caps),
    atomic_list_concat(Caps, Base0),
    (   Base0 == '' -> Base1 = 'V'
    ;   sub_atom(Base0, 0, 1, _, C), char_type(C, digit) -> atom_concat('V', Base0, Base1)
    ;   Base1 = Base0
    ),
    unique_name(Base1, Used, 1, PN).

split_words(Cs, Words) :-
    foldl([C, W0-Ws0, W-Ws]>>( code_type(C, alnum) -> W = [C|W0], Ws = Ws0
                              ; W0 == [] -> W = [], Ws = Ws0
                              ; W = [], Ws = [W0|Ws0] ), Cs, []-[], Last-Rev),
    ( Last == [] -> All = Rev ; All = [Last|Rev] ),
    reverse(All, RevWords), maplist(reverse, RevWords, Ws1), maplist([X, A]>>atom_codes(A, X), Ws1, Words).

capitalise(W, C) :-
    sub_atom(W, 0, 1, _, F), sub_atom(W, 1, _, 0, R), upcase_atom(F, FU), atom_concat(FU, R, C).

unique_name(B, Used, _, B) :- \+ memberchk(B, Used), !.
unique_name(B, Used, N, PN) :- atom_concat(B, N, C), ( \+ memberchk(C, Used) -> PN = C ; N1 is N + 1, unique_name(B, Used, N1, PN) ).

strip_module_goal(gaps_engine:builtin(A), A) :- !.
strip_module_goal(gaps_engine:aggregate(K, R, X, _:G), aggregate(K, R, X, G1)) :- !, strip_module_goal(G, G1).
strip_module_goal((A, B), (A1, B1)) :- !, strip_module_goal(A, A1), strip_module_goal(B, B1).
strip_module_goal((A ; B), (A1 ; B1)) :- !, strip_module_goal(A, A1), strip_module_goal(B, B1).
strip_module_goal(\+ A, \+ A1) :- !, strip_module_goal(A, A1).
strip_module_goal(G, G).
